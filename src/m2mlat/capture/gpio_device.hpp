// The Linux GPIO character device (uAPI v2), behind a small interface so that everything above it
// (chip lookup, line requests, event decoding, gap detection) runs the same against the kernel and
// against the in-process twin (fake_gpio.hpp). The kernel's own structs from <linux/gpio.h> cross
// this interface unchanged: their layout is the kernel header's on every architecture, never a copy.
//
// Failures of the system calls are thrown as std::system_error carrying errno; explain_gpio_error
// (chip_lookup.hpp) turns them into messages that say how to fix them (permissions, a line held by
// another program).
#pragma once

#include <linux/gpio.h>

#include <cstddef>
#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <vector>

namespace m2mlat::capture {

// The largest event buffer the kernel grants a request (it clamps larger requests to this).
inline constexpr std::uint32_t kMaxEventBufferSize = GPIO_V2_LINES_MAX * 16;

struct ChipInfo {
  std::string path;   // /dev/gpiochip4
  std::string name;   // gpiochip4
  std::string label;  // pinctrl-rp1, gpio-sim.0-node0, ...
  std::uint32_t lines = 0;
};

struct LineInfo {
  std::uint32_t offset = 0;
  std::string name;               // GPIO16; may be empty
  std::string consumer;           // who holds it; empty if free
  std::uint64_t flags = 0;        // GPIO_V2_LINE_FLAG_* bits
  std::uint32_t debounce_us = 0;  // the debounce attribute, if set
  bool used() const { return (flags & GPIO_V2_LINE_FLAG_USED) != 0; }
};

// One granted line request: owns its descriptor.
class LineRequest {
 public:
  virtual ~LineRequest() = default;
  // Polls readable when events are waiting. Non-blocking.
  virtual int fd() const = 0;
  // Reads up to out.size() waiting events without blocking; returns how many (0: none waiting).
  virtual std::size_t read_events(std::span<gpio_v2_line_event> out) = 0;
  // Sets the output values: bit i of `bits` for line i of the request, where bit i of `mask` is set.
  virtual void set_values(std::uint64_t bits, std::uint64_t mask) = 0;
};

// The chips a process sees.
class GpioDevices {
 public:
  virtual ~GpioDevices() = default;
  // Every chip's device path, sorted by chip number.
  virtual std::vector<std::string> chip_paths() const = 0;
  virtual ChipInfo chip_info(const std::string& path) const = 0;
  virtual LineInfo line_info(const std::string& path, std::uint32_t offset) const = 0;
  // GPIO_V2_GET_LINE_IOCTL with `request` (the kernel fills request.fd).
  virtual std::unique_ptr<LineRequest> request_lines(const std::string& path,
                                                     gpio_v2_line_request& request) = 0;
};

// The real character devices under `dev_dir` (/dev).
std::unique_ptr<GpioDevices> linux_gpio_devices(const std::string& dev_dir = "/dev");

}  // namespace m2mlat::capture
