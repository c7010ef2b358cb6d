// The in-process twin of a chip's register file, for the driver's unit tests (as fake_gpio is for
// the GPIO code): 256 byte registers, plus what an MPU-6050 does beyond plain memory: its FIFO
// (reads of FIFO_R_W pop bytes, FIFO_COUNT_H/L give the count), INT_STATUS cleared by reading it.
// It logs every write, can run a hook before each read (a test turns the "chip" there), and can be
// told to fail from some transfer on, or to be absent, as a real bus fails (errno EREMOTEIO).
#pragma once

#include <array>
#include <cstdint>
#include <deque>
#include <functional>
#include <string>
#include <utility>
#include <vector>

#include "m2mlat/capture/register_bus.hpp"

namespace m2mlat::capture {

class RegisterTwin final : public RegisterBus {
 public:
  std::uint8_t read_byte(std::uint8_t reg) override;
  void write_byte(std::uint8_t reg, std::uint8_t value) override;
  void read_block(std::uint8_t reg, std::span<std::uint8_t> out) override;
  std::string describe() const override { return "twin address 0x68"; }

  std::array<std::uint8_t, 256> registers{};
  std::deque<std::uint8_t> fifo;  // bytes the chip has put in its FIFO, oldest first
  std::vector<std::pair<std::uint8_t, std::uint8_t>> writes;  // (register, value), in order
  std::function<void()> before_read;                          // run before every read transfer
  // Transfers (reads and writes) left before every transfer fails; negative: never.
  long fail_after = -1;
  bool absent = false;  // no chip at all: every transfer fails
  std::uint64_t transfers = 0;

  // Puts x, y, z into the gyro output registers (big-endian, as the chip does).
  void set_rates(std::int16_t x, std::int16_t y, std::int16_t z);
  // Appends one gyro sample (6 bytes, big-endian) to the FIFO.
  void push_fifo(std::int16_t x, std::int16_t y, std::int16_t z);

 private:
  void transfer(std::uint8_t reg);
  std::uint8_t load(std::uint8_t reg);
};

}  // namespace m2mlat::capture
