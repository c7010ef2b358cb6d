// One chip on a Linux I2C bus through the I2C character device (/dev/i2c-N, module i2c-dev): the
// device opened, the chip's address selected (I2C_SLAVE), and SMBus transfers through the I2C_SMBUS
// ioctl. SMBus rather than plain I2C transfers (read(2), I2C_RDWR) because every controller that
// matters supports it (the Raspberry Pi's, and the kernel's i2c-stub that the real-kernel tests use,
// which speaks SMBus only). Move-only: the descriptor is closed when the handle goes.
#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <string_view>

#include "m2mlat/capture/register_bus.hpp"
#include "m2mlat/core/fd.hpp"

namespace m2mlat::capture {

class I2cBus final : public RegisterBus {
 public:
  // Opens `device` read-write and selects the 7-bit `address` (0x03..0x77). Throws core::Error:
  // no_input when the device does not exist (with the fix: load i2c-dev, enable the bus), io when it
  // cannot be opened or the address is refused (EBUSY: a kernel driver owns the chip), usage for an
  // address out of range. Nothing is sent to the chip yet: a missing chip shows at the first transfer.
  I2cBus(std::string device, std::uint8_t address);
  I2cBus(I2cBus&&) noexcept = default;
  I2cBus& operator=(I2cBus&&) noexcept = default;
  I2cBus(const I2cBus&) = delete;
  I2cBus& operator=(const I2cBus&) = delete;
  ~I2cBus() override = default;

  std::uint8_t read_byte(std::uint8_t reg) override;
  void write_byte(std::uint8_t reg, std::uint8_t value) override;
  void read_block(std::uint8_t reg, std::span<std::uint8_t> out) override;
  // Several consecutive registers from `reg` in one transfer (1..32 bytes).
  void write_block(std::uint8_t reg, std::span<const std::uint8_t> data);
  std::string describe() const override;

  const std::string& device() const { return device_; }
  std::uint8_t address() const { return address_; }

 private:
  std::string device_;
  std::uint8_t address_ = 0;
  core::Fd fd_;
};

// "0x68", "104": a 7-bit address (0x03..0x77); throws core::Error(usage) naming `flag` otherwise.
std::uint8_t parse_i2c_address(std::string_view flag, std::string_view text);

}  // namespace m2mlat::capture
