#include "m2mlat/capture/register_twin.hpp"

#include <fmt/format.h>

#include "m2mlat/capture/mpu6050.hpp"
#include "m2mlat/core/error.hpp"

namespace m2mlat::capture {

void RegisterTwin::transfer(std::uint8_t reg) {
  ++transfers;
  if (absent || fail_after == 0)
    throw core::Error(
        core::ErrorKind::io,
        fmt::format("{}: register 0x{:02x}: Remote I/O error (no chip answered)", describe(), reg));
  if (fail_after > 0) --fail_after;
}

std::uint8_t RegisterTwin::load(std::uint8_t reg) {
  namespace r = mpu6050::reg;
  switch (reg) {
    case r::fifo_r_w: {
      if (fifo.empty()) return 0xff;  // the chip's answer to reading an empty FIFO
      const std::uint8_t b = fifo.front();
      fifo.pop_front();
      return b;
    }
    case r::fifo_count_h: return static_cast<std::uint8_t>(fifo.size() >> 8);
    case r::fifo_count_l: return static_cast<std::uint8_t>(fifo.size() & 0xff);
    case r::int_status: return std::exchange(registers[reg], 0);  // cleared by reading it
    default: return registers[reg];
  }
}

std::uint8_t RegisterTwin::read_byte(std::uint8_t reg) {
  if (before_read) before_read();
  transfer(reg);
  return load(reg);
}

void RegisterTwin::write_byte(std::uint8_t reg, std::uint8_t value) {
  transfer(reg);
  writes.emplace_back(reg, value);
  if (reg == mpu6050::reg::user_ctrl && (value & mpu6050::user_ctrl_fifo_reset)) fifo.clear();
  // The reset bits clear themselves on the chip.
  registers[reg] = reg == mpu6050::reg::user_ctrl
                       ? static_cast<std::uint8_t>(value & ~mpu6050::user_ctrl_fifo_reset)
                       : value;
}

void RegisterTwin::read_block(std::uint8_t reg, std::span<std::uint8_t> out) {
  if (before_read) before_read();
  transfer(reg);
  // The FIFO's data register does not advance: a burst read of it gives successive FIFO bytes.
  for (std::size_t i = 0; i < out.size(); ++i)
    out[i] = load(reg == mpu6050::reg::fifo_r_w ? reg : static_cast<std::uint8_t>(reg + i));
}

void RegisterTwin::set_rates(std::int16_t x, std::int16_t y, std::int16_t z) {
  std::size_t at = mpu6050::reg::gyro_xout_h;
  for (const std::int16_t v : {x, y, z}) {
    const auto u = static_cast<std::uint16_t>(v);
    registers[at++] = static_cast<std::uint8_t>(u >> 8);
    registers[at++] = static_cast<std::uint8_t>(u & 0xff);
  }
}

void RegisterTwin::push_fifo(std::int16_t x, std::int16_t y, std::int16_t z) {
  for (const std::int16_t v : {x, y, z}) {
    const auto u = static_cast<std::uint16_t>(v);
    fifo.push_back(static_cast<std::uint8_t>(u >> 8));
    fifo.push_back(static_cast<std::uint8_t>(u & 0xff));
  }
}

}  // namespace m2mlat::capture
