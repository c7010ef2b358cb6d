// Register access on one chip behind a bus (an I2C device at one address): the small interface the
// MPU-6050 driver is written against, so that the same driver runs on Linux's I2C character device
// (i2c_bus.hpp) and, in the unit tests, on an in-process register file (register_twin.hpp).
// Every call either does what it says or throws core::Error naming the device, the address and the
// register.
#pragma once

#include <cstdint>
#include <span>
#include <string>

namespace m2mlat::capture {

class RegisterBus {
 public:
  virtual ~RegisterBus() = default;

  // One register (SMBus "read byte data").
  virtual std::uint8_t read_byte(std::uint8_t reg) = 0;
  // One register (SMBus "write byte data").
  virtual void write_byte(std::uint8_t reg, std::uint8_t value) = 0;
  // out.size() consecutive registers from `reg` in one transfer (SMBus "I2C block data", 1..32 bytes;
  // a chip's FIFO data register gives successive FIFO bytes instead).
  virtual void read_block(std::uint8_t reg, std::span<std::uint8_t> out) = 0;
  // "/dev/i2c-1 address 0x68": the start of every error message about this chip.
  virtual std::string describe() const = 0;
};

// The largest block an SMBus I2C-block transfer carries, bytes.
inline constexpr std::size_t kMaxBlockBytes = 32;

}  // namespace m2mlat::capture
