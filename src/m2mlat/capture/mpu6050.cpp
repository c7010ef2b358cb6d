#include "m2mlat/capture/mpu6050.hpp"

#include <fmt/format.h>

#include "m2mlat/core/error.hpp"

namespace m2mlat::capture {

std::array<std::int16_t, 3> decode_rates(std::span<const std::uint8_t, 6> bytes) {
  std::array<std::int16_t, 3> out{};
  for (std::size_t i = 0; i < 3; ++i)
    out[i] = static_cast<std::int16_t>(static_cast<std::uint16_t>((bytes[2 * i] << 8) | bytes[2 * i + 1]));
  return out;
}

Mpu6050::Mpu6050(RegisterBus& bus) : bus_(bus) {
  const std::uint8_t who = bus_.read_byte(mpu6050::reg::who_am_i);
  if (who != mpu6050::kWhoAmI)
    throw core::Error(core::ErrorKind::io,
                      fmt::format("{}: a chip that is not an MPU-6050 (WHO_AM_I 0x{:02x}, expected 0x{:02x})",
                                  bus_.describe(), who, mpu6050::kWhoAmI));
}

void Mpu6050::write_checked(std::uint8_t reg, std::uint8_t value) {
  bus_.write_byte(reg, value);
  const std::uint8_t back = bus_.read_byte(reg);
  if (back != value)
    throw core::Error(core::ErrorKind::io,
                      fmt::format("{}: register 0x{:02x} reads 0x{:02x} after writing 0x{:02x}",
                                  bus_.describe(), reg, back, value));
}

void Mpu6050::configure(const Mpu6050Config& config) {
  namespace r = mpu6050::reg;
  write_checked(r::pwr_mgmt_1, mpu6050::pwr_clock_pll_x);  // wake first: a sleeping chip samples nothing
  write_checked(r::smplrt_div, config.sample_rate_divider);
  write_checked(r::config, 0x00);       // no FSYNC, DLPF_CFG 0: gyro at 8 kHz
  write_checked(r::gyro_config, 0x00);  // no self-test, FS_SEL 0: +-250 deg/s
  // FIFO: stop it, reset it (the reset bit clears itself), then let the gyro axes in.
  write_checked(r::fifo_en, 0x00);
  bus_.write_byte(r::user_ctrl, mpu6050::user_ctrl_fifo_reset);
  if (config.fifo) {
    write_checked(r::user_ctrl, mpu6050::user_ctrl_fifo_en);
    write_checked(r::fifo_en, mpu6050::fifo_en_gyro_xyz);
  } else {
    write_checked(r::user_ctrl, 0x00);
  }
  write_checked(r::int_pin_cfg, 0x00);  // active high, push-pull, a 50 us pulse, cleared by INT_STATUS
  write_checked(r::int_enable,
                static_cast<std::uint8_t>((config.data_ready_interrupt ? mpu6050::int_data_ready : 0) |
                                          (config.fifo ? mpu6050::int_fifo_overflow : 0)));
  (void)bus_.read_byte(r::int_status);  // clear what was flagged before
}

std::array<std::int16_t, 3> Mpu6050::read_rates() {
  std::array<std::uint8_t, 6> bytes{};
  bus_.read_block(mpu6050::reg::gyro_xout_h, bytes);
  return decode_rates(bytes);
}

FifoRead Mpu6050::read_fifo() {
  namespace r = mpu6050::reg;
  FifoRead out;
  out.overflow = (bus_.read_byte(r::int_status) & mpu6050::int_fifo_overflow) != 0;
  if (out.overflow) {
    // The chip overwrote the oldest bytes, so the data may no longer start on a sample's first byte:
    // drop all of it and start again aligned.
    bus_.write_byte(r::user_ctrl, mpu6050::user_ctrl_fifo_en | mpu6050::user_ctrl_fifo_reset);
    return out;
  }
  std::array<std::uint8_t, 2> count_bytes{};
  bus_.read_block(r::fifo_count_h, count_bytes);
  const std::size_t count = (std::size_t{count_bytes[0]} << 8) | count_bytes[1];
  const std::size_t whole = count / mpu6050::kSampleBytes;
  constexpr std::size_t kPerBurst = kMaxBlockBytes / mpu6050::kSampleBytes;  // 5 samples, 30 bytes
  std::array<std::uint8_t, kPerBurst * mpu6050::kSampleBytes> burst{};
  for (std::size_t done = 0; done < whole;) {
    const std::size_t n = std::min(kPerBurst, whole - done);
    const std::span<std::uint8_t> bytes(burst.data(), n * mpu6050::kSampleBytes);
    bus_.read_block(r::fifo_r_w, bytes);
    for (std::size_t i = 0; i < n; ++i)
      out.samples.push_back(decode_rates(std::span<const std::uint8_t, 6>(bytes.subspan(i * 6, 6))));
    done += n;
  }
  return out;
}

}  // namespace m2mlat::capture
