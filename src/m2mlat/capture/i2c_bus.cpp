// The I2C_SMBUS ioctl by hand (no libi2c): the request is a read/write flag, a register and a size
// code, with the data in a union of at most 34 bytes (length byte, 32 data bytes, PEC).
#include "m2mlat/capture/i2c_bus.hpp"

#include <fcntl.h>
#include <fmt/format.h>
#include <linux/i2c-dev.h>
#include <linux/i2c.h>
#include <sys/ioctl.h>

#include <cerrno>
#include <cstring>

#include "m2mlat/core/error.hpp"
#include "m2mlat/core/number.hpp"

namespace m2mlat::capture {

namespace {

// One SMBus transfer; returns 0 or errno.
int smbus(int fd, std::uint8_t read_write, std::uint8_t reg, std::uint32_t size, i2c_smbus_data* data) {
  i2c_smbus_ioctl_data args{};
  args.read_write = read_write;
  args.command = reg;
  args.size = size;
  args.data = data;
  return ::ioctl(fd, I2C_SMBUS, &args) == 0 ? 0 : errno;
}

// What an errno from a transfer means for the user: the chip not answering (nothing at that
// address, not powered, SDA/SCL not wired) is EREMOTEIO or ENXIO from most controllers (the
// Raspberry Pi's: EREMOTEIO), ENODEV from i2c-stub, EIO from some.
std::string transfer_hint(int err) {
  if (err == ENXIO || err == EREMOTEIO || err == EIO || err == ENODEV)
    return " (no chip answered at that address: check its power, SDA/SCL wiring and address pin; i2cdetect "
           "lists what answers)";
  if (err == EOPNOTSUPP) return " (the bus controller does not support this SMBus transfer)";
  return "";
}

}  // namespace

std::uint8_t parse_i2c_address(std::string_view flag, std::string_view text) {
  unsigned value = 0;
  const bool hex = text.starts_with("0x") || text.starts_with("0X");
  if (!core::parse_integer(hex ? text.substr(2) : text, value, hex ? 16 : 10) || value < 0x03 || value > 0x77)
    throw core::Error(core::ErrorKind::usage,
                      fmt::format("{}: '{}' is not a 7-bit I2C address (0x03..0x77)", flag, text));
  return static_cast<std::uint8_t>(value);
}

I2cBus::I2cBus(std::string device, std::uint8_t address) : device_(std::move(device)), address_(address) {
  if (address_ < 0x03 || address_ > 0x77)
    throw core::Error(
        core::ErrorKind::usage,
        fmt::format("I2C address 0x{:02x} is not a 7-bit device address (0x03..0x77)", address_));
  fd_.reset(::open(device_.c_str(), O_RDWR | O_CLOEXEC));
  if (!fd_) {
    const int err = errno;
    if (err == ENOENT)
      throw core::Error(core::ErrorKind::no_input,
                        fmt::format("{}: no such I2C device (load i2c-dev, and enable the bus: on a "
                                    "Raspberry Pi dtparam=i2c_arm=on; see docs/hardware.md)",
                                    device_));
    throw core::Error(core::ErrorKind::io,
                      fmt::format("{}: cannot open: {}{}", device_, std::strerror(err),
                                  err == EACCES ? " (add the user to group i2c, or run as root)" : ""));
  }
  if (::ioctl(fd_.get(), I2C_SLAVE, static_cast<unsigned long>(address_)) != 0) {
    const int err = errno;
    throw core::Error(
        core::ErrorKind::io,
        fmt::format("{}: cannot select address 0x{:02x}: {}{}", device_, address_, std::strerror(err),
                    err == EBUSY ? " (a kernel driver owns this chip: unbind it first)" : ""));
  }
}

std::string I2cBus::describe() const { return fmt::format("{} address 0x{:02x}", device_, address_); }

std::uint8_t I2cBus::read_byte(std::uint8_t reg) {
  i2c_smbus_data data{};
  if (const int err = smbus(fd_.get(), I2C_SMBUS_READ, reg, I2C_SMBUS_BYTE_DATA, &data))
    throw core::Error(core::ErrorKind::io, fmt::format("{}: reading register 0x{:02x}: {}{}", describe(), reg,
                                                       std::strerror(err), transfer_hint(err)));
  return data.byte;
}

void I2cBus::write_byte(std::uint8_t reg, std::uint8_t value) {
  i2c_smbus_data data{};
  data.byte = value;
  if (const int err = smbus(fd_.get(), I2C_SMBUS_WRITE, reg, I2C_SMBUS_BYTE_DATA, &data))
    throw core::Error(core::ErrorKind::io,
                      fmt::format("{}: writing 0x{:02x} to register 0x{:02x}: {}{}", describe(), value, reg,
                                  std::strerror(err), transfer_hint(err)));
}

void I2cBus::read_block(std::uint8_t reg, std::span<std::uint8_t> out) {
  if (out.empty() || out.size() > kMaxBlockBytes)
    throw core::Error(core::ErrorKind::internal,
                      fmt::format("{}: block read of {} bytes (1..32)", describe(), out.size()));
  i2c_smbus_data data{};
  data.block[0] = static_cast<std::uint8_t>(out.size());
  if (const int err = smbus(fd_.get(), I2C_SMBUS_READ, reg, I2C_SMBUS_I2C_BLOCK_DATA, &data))
    throw core::Error(core::ErrorKind::io,
                      fmt::format("{}: reading {} bytes from register 0x{:02x}: {}{}", describe(), out.size(),
                                  reg, std::strerror(err), transfer_hint(err)));
  if (data.block[0] != out.size())
    throw core::Error(core::ErrorKind::io, fmt::format("{}: reading {} bytes from register 0x{:02x}: got {}",
                                                       describe(), out.size(), reg, data.block[0]));
  std::memcpy(out.data(), &data.block[1], out.size());
}

void I2cBus::write_block(std::uint8_t reg, std::span<const std::uint8_t> bytes) {
  if (bytes.empty() || bytes.size() > kMaxBlockBytes)
    throw core::Error(core::ErrorKind::internal,
                      fmt::format("{}: block write of {} bytes (1..32)", describe(), bytes.size()));
  i2c_smbus_data data{};
  data.block[0] = static_cast<std::uint8_t>(bytes.size());
  std::memcpy(&data.block[1], bytes.data(), bytes.size());
  if (const int err = smbus(fd_.get(), I2C_SMBUS_WRITE, reg, I2C_SMBUS_I2C_BLOCK_DATA, &data))
    throw core::Error(core::ErrorKind::io,
                      fmt::format("{}: writing {} bytes to register 0x{:02x}: {}{}", describe(), bytes.size(),
                                  reg, std::strerror(err), transfer_hint(err)));
}

}  // namespace m2mlat::capture
