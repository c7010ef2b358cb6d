// Finding a chip by path (/dev/gpiochip4), name (gpiochip4) or label (pinctrl-rp1, gpio-sim.0-node0),
// and a line by offset (16) or name (GPIO16); and turning the uAPI's errno into a message that says
// what to do (permissions, a line held by another program, a chip that does not exist).
#pragma once

#include <cstdint>
#include <string>
#include <string_view>
#include <system_error>

#include "m2mlat/capture/gpio_device.hpp"
#include "m2mlat/core/error.hpp"

namespace m2mlat::capture {

// Throws core::Error: no_input listing the chips there are (or saying there are none), io for a
// chip that cannot be opened (with the fix).
ChipInfo find_chip(const GpioDevices& devices, std::string_view spec);
// The offset of line `spec` on `chip`: a number below chip.lines, or a line name. Throws
// core::Error(no_input) naming the chip and its number of lines.
std::uint32_t find_line(const GpioDevices& devices, const ChipInfo& chip, std::string_view spec);

// A failed uAPI call on `chip` (line `offset`, if it concerns one) as a core::Error with the fix.
core::Error explain_gpio_error(const std::system_error& error, const GpioDevices& devices,
                               const ChipInfo& chip, std::int64_t offset = -1);
// The advice for a chip device the user may not open.
std::string permission_advice(const std::string& path);

}  // namespace m2mlat::capture
