// The InvenSense MPU-6050 gyroscope (its register map, revision 4.2): identification, the
// configuration m2mlat reads it in, and the two ways of getting its angular rate out: the output
// registers read directly (one 6-byte burst, the polling source) and the FIFO read in bursts (for a
// reader woken by the data-ready pin). Written against RegisterBus, so the same code runs on
// /dev/i2c-N and on the in-process twin.
//
// Configuration: awake with the X gyro's PLL as clock (steadier than the internal 8 MHz oscillator),
// the digital low-pass filter off (DLPF_CFG 0: the gyro is sampled at 8 kHz, with the least delay,
// about 0.1 ms), SMPLRT_DIV setting the output rate (8 kHz / (1 + divider)), full scale +-250 deg/s
// (131 counts per deg/s, the finest resolution). Every register written is read back.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "m2mlat/capture/register_bus.hpp"

namespace m2mlat::capture {

namespace mpu6050 {

namespace reg {
inline constexpr std::uint8_t smplrt_div = 0x19;
inline constexpr std::uint8_t config = 0x1a;
inline constexpr std::uint8_t gyro_config = 0x1b;
inline constexpr std::uint8_t fifo_en = 0x23;
inline constexpr std::uint8_t int_pin_cfg = 0x37;
inline constexpr std::uint8_t int_enable = 0x38;
inline constexpr std::uint8_t int_status = 0x3a;
inline constexpr std::uint8_t gyro_xout_h = 0x43;  // ..0x48: x, y, z, each high byte first
inline constexpr std::uint8_t user_ctrl = 0x6a;
inline constexpr std::uint8_t pwr_mgmt_1 = 0x6b;
inline constexpr std::uint8_t fifo_count_h = 0x72;
inline constexpr std::uint8_t fifo_count_l = 0x73;
inline constexpr std::uint8_t fifo_r_w = 0x74;
inline constexpr std::uint8_t who_am_i = 0x75;
}  // namespace reg

inline constexpr std::uint8_t kDefaultAddress = 0x68;   // AD0 low (0x69 with AD0 high)
inline constexpr std::uint8_t kWhoAmI = 0x68;           // WHO_AM_I's value whatever AD0 is
inline constexpr std::uint8_t pwr_clock_pll_x = 0x01;   // PWR_MGMT_1: CLKSEL 1, SLEEP 0
inline constexpr std::uint8_t fifo_en_gyro_xyz = 0x70;  // FIFO_EN: XG, YG, ZG
inline constexpr std::uint8_t user_ctrl_fifo_en = 0x40;
inline constexpr std::uint8_t user_ctrl_fifo_reset = 0x04;
inline constexpr std::uint8_t int_data_ready = 0x01;     // INT_ENABLE / INT_STATUS: DATA_RDY
inline constexpr std::uint8_t int_fifo_overflow = 0x10;  // INT_ENABLE / INT_STATUS: FIFO_OFLOW
inline constexpr double kCountsPerDegS = 131.0;          // at FS_SEL 0 (+-250 deg/s)
inline constexpr std::int64_t kGyroRateHz = 8000;        // with the DLPF off
inline constexpr std::size_t kFifoBytes = 1024;
inline constexpr std::size_t kSampleBytes = 6;  // one gyro sample (x, y, z) in the FIFO

}  // namespace mpu6050

struct Mpu6050Config {
  std::uint8_t sample_rate_divider = 0;  // output rate 8 kHz / (1 + divider)
  bool fifo = false;                     // gyro x, y, z into the FIFO at the output rate
  // The INT pin pulses high for 50 us at each new sample (push-pull, active high, not latched): for
  // a GPIO line stamped in the kernel's interrupt handler.
  bool data_ready_interrupt = false;
};

// One burst read out of the FIFO.
struct FifoRead {
  std::vector<std::array<std::int16_t, 3>> samples;  // oldest first
  // The FIFO overflowed since the last read: samples were lost (how many is unknown; the FIFO was
  // reset so that reading stays aligned on whole samples). Reported, never hidden.
  bool overflow = false;
};

class Mpu6050 {
 public:
  // Reads WHO_AM_I; throws core::Error(io) naming the bus and what was read when it is not 0x68
  // ("a chip at 0x68 that is not an MPU-6050 (WHO_AM_I 0x70)"), or the bus's error when nothing
  // answers. The chip is not changed.
  explicit Mpu6050(RegisterBus& bus);

  // Wakes and configures the chip (see the top of this file); throws core::Error(io) when a register
  // does not read back as written.
  void configure(const Mpu6050Config& config);

  // The gyro output registers in one 6-byte block read: x, y, z in counts.
  std::array<std::int16_t, 3> read_rates();

  // Whole samples out of the FIFO (bursts of up to 30 bytes, whole samples only), and whether it
  // overflowed since the last read.
  FifoRead read_fifo();

  RegisterBus& bus() { return bus_; }

 private:
  void write_checked(std::uint8_t reg, std::uint8_t value);
  RegisterBus& bus_;
};

// Big-endian signed 16-bit x, y, z from the six bytes GYRO_XOUT_H..GYRO_ZOUT_L.
std::array<std::int16_t, 3> decode_rates(std::span<const std::uint8_t, 6> bytes);

}  // namespace m2mlat::capture
