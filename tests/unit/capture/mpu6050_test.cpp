// The MPU-6050 driver against the in-process register twin: identification, the configuration it
// writes (and checks by reading back), byte order and sign of the rates, the FIFO's counts and an
// overflow reported as a loss.
#include "m2mlat/capture/mpu6050.hpp"

#include <gtest/gtest.h>

#include <vector>

#include "m2mlat/capture/register_twin.hpp"
#include "m2mlat/core/error.hpp"

namespace m2mlat::capture::mpu6050_test {
namespace {

namespace r = mpu6050::reg;

RegisterTwin mpu() {
  RegisterTwin twin;
  twin.registers[r::who_am_i] = 0x68;
  twin.registers[r::pwr_mgmt_1] = 0x40;  // the chip's state after power-on: asleep
  return twin;
}

TEST(Mpu6050, RefusesAChipWhoseWhoAmIIsNot0x68AndNamesWhatItRead) {
  RegisterTwin twin = mpu();
  twin.registers[r::who_am_i] = 0x70;  // an MPU-6500
  try {
    Mpu6050 chip(twin);
    FAIL() << "no error";
  } catch (const core::Error& e) {
    EXPECT_EQ(e.kind(), core::ErrorKind::io);
    EXPECT_NE(std::string(e.what()).find("not an MPU-6050 (WHO_AM_I 0x70"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("address 0x68"), std::string::npos) << e.what();
  }
  EXPECT_TRUE(twin.writes.empty());  // nothing was changed on a chip that is not ours
}

TEST(Mpu6050, AMissingChipGivesTheBussError) {
  RegisterTwin twin = mpu();
  twin.absent = true;
  try {
    Mpu6050 chip(twin);
    FAIL() << "no error";
  } catch (const core::Error& e) {
    EXPECT_NE(std::string(e.what()).find("register 0x75"), std::string::npos) << e.what();
  }
}

TEST(Mpu6050, ConfigureWakesOnThePllWithTheFilterOffAt250DegPerS) {
  RegisterTwin twin = mpu();
  Mpu6050 chip(twin);
  chip.configure({.sample_rate_divider = 7, .fifo = false, .data_ready_interrupt = true});
  ASSERT_FALSE(twin.writes.empty());
  EXPECT_EQ(twin.writes.front(), std::make_pair(r::pwr_mgmt_1, std::uint8_t{0x01}));  // woken first
  EXPECT_EQ(twin.registers[r::pwr_mgmt_1], 0x01);
  EXPECT_EQ(twin.registers[r::smplrt_div], 7);
  EXPECT_EQ(twin.registers[r::config], 0x00);       // DLPF_CFG 0: 8 kHz
  EXPECT_EQ(twin.registers[r::gyro_config], 0x00);  // FS_SEL 0: 131 counts per deg/s
  EXPECT_EQ(twin.registers[r::fifo_en], 0x00);
  EXPECT_EQ(twin.registers[r::user_ctrl], 0x00);
  EXPECT_EQ(twin.registers[r::int_pin_cfg], 0x00);  // active high, push-pull, pulsed
  EXPECT_EQ(twin.registers[r::int_enable], mpu6050::int_data_ready);
}

TEST(Mpu6050, ConfigureWithTheFifoLetsTheThreeGyroAxesInAndWatchesOverflow) {
  RegisterTwin twin = mpu();
  twin.push_fifo(1, 2, 3);  // stale data from before: reset away
  Mpu6050 chip(twin);
  chip.configure({.sample_rate_divider = 0, .fifo = true, .data_ready_interrupt = false});
  EXPECT_TRUE(twin.fifo.empty());
  EXPECT_EQ(twin.registers[r::user_ctrl], mpu6050::user_ctrl_fifo_en);
  EXPECT_EQ(twin.registers[r::fifo_en], 0x70);
  EXPECT_EQ(twin.registers[r::int_enable], mpu6050::int_fifo_overflow);
}

TEST(Mpu6050, ARegisterThatDoesNotReadBackIsAnError) {
  RegisterTwin twin = mpu();
  Mpu6050 chip(twin);
  // A chip that ignores writes to GYRO_CONFIG (stuck at +-2000 deg/s).
  twin.before_read = [&] { twin.registers[r::gyro_config] = 0x18; };
  try {
    chip.configure({});
    FAIL() << "no error";
  } catch (const core::Error& e) {
    EXPECT_NE(std::string(e.what()).find("register 0x1b reads 0x18 after writing 0x00"), std::string::npos)
        << e.what();
  }
}

TEST(Mpu6050, RatesAreBigEndianSigned16BitInOneBlockRead) {
  RegisterTwin twin = mpu();
  Mpu6050 chip(twin);
  // x = 0x1234, y = -2 (0xfffe), z = -32768 (0x8000)
  const std::uint8_t bytes[] = {0x12, 0x34, 0xff, 0xfe, 0x80, 0x00};
  std::copy(std::begin(bytes), std::end(bytes), twin.registers.begin() + r::gyro_xout_h);
  const auto before = twin.transfers;
  const auto rates = chip.read_rates();
  EXPECT_EQ(twin.transfers, before + 1);  // one transfer: the three axes belong to one sample
  EXPECT_EQ(rates[0], 0x1234);
  EXPECT_EQ(rates[1], -2);
  EXPECT_EQ(rates[2], -32768);
  twin.set_rates(131, -131, 32767);
  EXPECT_EQ(chip.read_rates(), (std::array<std::int16_t, 3>{131, -131, 32767}));
}

TEST(Mpu6050, FifoGivesWholeSamplesInOrderAndLeavesAPartialOne) {
  RegisterTwin twin = mpu();
  Mpu6050 chip(twin);
  chip.configure({.sample_rate_divider = 0, .fifo = true, .data_ready_interrupt = false});
  for (std::int16_t i = 0; i < 12; ++i)
    twin.push_fifo(i, static_cast<std::int16_t>(-i), static_cast<std::int16_t>(1000 * i));
  twin.fifo.push_back(0x7f);  // the first byte of a sample the chip is still writing
  const auto read = chip.read_fifo();
  EXPECT_FALSE(read.overflow);
  ASSERT_EQ(read.samples.size(), 12u);  // 12 samples: bursts of 5, 5 and 2
  for (std::int16_t i = 0; i < 12; ++i)
    EXPECT_EQ(read.samples[i], (std::array<std::int16_t, 3>{i, static_cast<std::int16_t>(-i),
                                                            static_cast<std::int16_t>(1000 * i)}));
  EXPECT_EQ(twin.fifo.size(), 1u);
}

TEST(Mpu6050, FifoOverflowIsReportedAsALossAndTheFifoRestartsAligned) {
  RegisterTwin twin = mpu();
  Mpu6050 chip(twin);
  chip.configure({.sample_rate_divider = 0, .fifo = true, .data_ready_interrupt = false});
  for (int i = 0; i < 170; ++i) twin.push_fifo(1, 2, 3);
  twin.fifo.pop_front();  // the chip overwrote the oldest byte: no longer aligned on a sample
  twin.registers[r::int_status] = mpu6050::int_fifo_overflow;
  const auto lost = chip.read_fifo();
  EXPECT_TRUE(lost.overflow);
  EXPECT_TRUE(lost.samples.empty());
  EXPECT_TRUE(twin.fifo.empty());                                       // reset
  EXPECT_EQ(twin.registers[r::user_ctrl], mpu6050::user_ctrl_fifo_en);  // and still on
  twin.push_fifo(4, 5, 6);
  const auto next = chip.read_fifo();
  EXPECT_FALSE(next.overflow);  // INT_STATUS was cleared by reading it
  ASSERT_EQ(next.samples.size(), 1u);
  EXPECT_EQ(next.samples[0], (std::array<std::int16_t, 3>{4, 5, 6}));
}

TEST(Mpu6050, DecodeRates) {
  const std::array<std::uint8_t, 6> bytes{0x00, 0x83, 0xff, 0x7d, 0x7f, 0xff};
  EXPECT_EQ(decode_rates(bytes), (std::array<std::int16_t, 3>{131, -131, 32767}));
}

}  // namespace
}  // namespace m2mlat::capture::mpu6050_test
