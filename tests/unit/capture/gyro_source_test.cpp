// The polling gyroscope source on the register twin: each reading stamped with an interval that
// holds the instant of the read, the values in order, periods missed by a slow bus counted, and an
// I2C error mid-run ending the run with the samples already taken kept.
#include "m2mlat/capture/gyro_source.hpp"

#include <gtest/gtest.h>
#include <time.h>

#include <chrono>
#include <thread>
#include <vector>

#include "m2mlat/capture/register_twin.hpp"

namespace m2mlat::capture::gyro_source_test {
namespace {

std::int64_t realtime_ns() {
  timespec ts{};
  clock_gettime(CLOCK_REALTIME, &ts);
  return std::int64_t{ts.tv_sec} * 1'000'000'000 + ts.tv_nsec;
}

RegisterTwin mpu() {
  RegisterTwin twin;
  twin.registers[mpu6050::reg::who_am_i] = 0x68;
  return twin;
}

void wait_until_stopped(GyroSource& source) {
  for (int i = 0; i < 5000 && source.running(); ++i)
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  source.join();
}

TEST(GyroSource, EachSampleIsStampedWithAnIntervalHoldingTheReadAndTheValuesInOrder) {
  RegisterTwin twin = mpu();
  Mpu6050 chip(twin);
  std::vector<std::int64_t> read_at;  // when the "chip" was read, CLOCK_REALTIME ns
  std::int16_t n = 0;
  twin.before_read = [&] {
    twin.set_rates(n, static_cast<std::int16_t>(-n), static_cast<std::int16_t>(2 * n));
    ++n;
    read_at.push_back(realtime_ns());
  };
  GyroSource source(chip,
                    {.period = std::chrono::microseconds(500), .duration = std::chrono::milliseconds(100)});
  source.start();
  wait_until_stopped(source);
  const auto samples = source.take();
  const auto summary = source.summary();
  EXPECT_EQ(summary.stop_reason, "duration");
  EXPECT_EQ(summary.reads, samples.size());
  EXPECT_EQ(summary.i2c_errors, 0u);
  // 200 periods in 100 ms: each either read or counted as missed.
  EXPECT_EQ(summary.reads + summary.missed_periods, 200u);
  ASSERT_GE(samples.size(), 20u);  // even on a loaded machine
  ASSERT_EQ(samples.size(), read_at.size());
  for (std::size_t i = 0; i < samples.size(); ++i) {
    const auto& s = samples[i];
    EXPECT_EQ(s.raw[0], static_cast<std::int16_t>(i));
    EXPECT_EQ(s.raw[1], static_cast<std::int16_t>(-static_cast<int>(i)));
    EXPECT_EQ(s.raw[2], static_cast<std::int16_t>(2 * i));
    EXPECT_GE(s.bound_ns, 0);
    // The values may have been sampled up to one output period (125 us) before the read.
    EXPECT_LE(s.time_ns - s.bound_ns, read_at[i] - 125'000) << i;
    EXPECT_GE(s.time_ns + s.bound_ns, read_at[i]) << i;
    if (i > 0) {
      EXPECT_GE(s.time_ns - samples[i - 1].time_ns, 0);
    }
  }
  EXPECT_LE(summary.min_read, summary.max_read);
  EXPECT_LE(samples.front().bound_ns * 2, summary.max_read.count() + 125'000 + 1);
  EXPECT_GE(samples.front().bound_ns * 2, 125'000);
}

TEST(GyroSource, ASlowBusMissesPeriodsAndTheyAreCounted) {
  RegisterTwin twin = mpu();
  Mpu6050 chip(twin);
  twin.before_read = [] { std::this_thread::sleep_for(std::chrono::milliseconds(3)); };
  GyroSource source(chip,
                    {.period = std::chrono::milliseconds(1), .duration = std::chrono::milliseconds(60)});
  source.start();
  wait_until_stopped(source);
  const auto summary = source.summary();
  EXPECT_GE(summary.reads, 3u);
  EXPECT_LE(summary.reads, 20u);  // at most one read per 3 ms
  EXPECT_EQ(summary.reads + summary.missed_periods, 60u);
  EXPECT_GE(summary.min_read, std::chrono::milliseconds(3));  // the read's duration is what was slow
  for (const auto& s : source.take()) EXPECT_GE(s.bound_ns, (3'000'000 + 125'000) / 2);
}

TEST(GyroSource, AnI2cErrorMidRunEndsTheRunKeepingTheSamplesTaken) {
  RegisterTwin twin = mpu();
  Mpu6050 chip(twin);
  twin.fail_after = 25;  // the chip stops answering after 25 reads
  GyroSource source(chip, {.period = std::chrono::microseconds(200)});  // no duration: until it fails
  source.start();
  wait_until_stopped(source);
  const auto summary = source.summary();
  EXPECT_EQ(summary.stop_reason, "i2c error");
  EXPECT_EQ(summary.i2c_errors, 1u);
  EXPECT_EQ(summary.reads, 25u);
  EXPECT_NE(summary.error.find("register 0x43"), std::string::npos) << summary.error;
  EXPECT_EQ(source.take().size(), 25u);
}

TEST(GyroSource, StopEndsAnOpenEndedRun) {
  RegisterTwin twin = mpu();
  Mpu6050 chip(twin);
  GyroSource source(chip, {.period = std::chrono::milliseconds(1)});
  source.start();
  // Until the first read is in (a fixed sleep is not enough on a loaded machine, where the thread may
  // not have run yet); 10 s is only a safety net.
  const auto limit = std::chrono::steady_clock::now() + std::chrono::seconds(10);
  while (source.summary().reads == 0 && std::chrono::steady_clock::now() < limit)
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  ASSERT_GE(source.summary().reads, 1u);
  EXPECT_TRUE(source.running());
  source.stop();
  source.join();
  EXPECT_EQ(source.summary().stop_reason, "stopped");
  EXPECT_GE(source.take().size(), 1u);
}

}  // namespace
}  // namespace m2mlat::capture::gyro_source_test
