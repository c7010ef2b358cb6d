// The LED's gyroscope trigger on the register twin: the sampler wakes the trigger after each sample,
// nothing is asked of the LED at rest, one flash is asked once the rotation starts (within a few
// read periods), and an I2C error ends the trigger with the error reported.
#include "m2mlat/capture/gyro_trigger.hpp"

#include <gtest/gtest.h>
#include <poll.h>

#include <atomic>
#include <memory>

#include "m2mlat/capture/mpu6050.hpp"
#include "m2mlat/capture/register_twin.hpp"
#include "m2mlat/core/clock_read.hpp"
#include "m2mlat/core/error.hpp"

namespace m2mlat::capture {
namespace {

GyroTriggerOptions trigger_options() {
  GyroTriggerOptions o;
  o.period = core::Duration{500'000};  // 2 kHz
  return o;
}

// Polls the trigger until `until` (monotonic ns) or its end; returns its actions' count.
struct TriggerRun {
  std::size_t flashes = 0;
  std::int64_t first_flash_ns = 0;  // CLOCK_REALTIME when the first flash was handed over
  bool ended = false;
  std::vector<std::string> refused;
};
TriggerRun run_trigger_until(GyroTrigger& trigger, std::int64_t until) {
  TriggerRun r;
  while (core::monotonic_now().count() < until && !r.ended) {
    pollfd fd{trigger.fd(), POLLIN, 0};
    ::poll(&fd, 1, 10);
    TriggerInput in;
    r.ended = !trigger.take(in);
    for (const auto a : in.actions) {
      EXPECT_EQ(a, LedAction::flash);
      if (r.flashes++ == 0) r.first_flash_ns = core::realtime_now().ns();
    }
    r.refused.insert(r.refused.end(), in.refused.begin(), in.refused.end());
  }
  return r;
}

TEST(GyroTrigger, AFlashAtTheRotationsOnsetAndNoneAtRest) {
  auto twin = std::make_unique<RegisterTwin>();
  twin->registers[mpu6050::reg::who_am_i] = 0x68;
  auto* t = twin.get();
  std::atomic<std::int16_t> rate{0};
  std::atomic<int> reads{0};
  twin->before_read = [t, &rate, &reads] {
    const int n = reads++;
    t->set_rates(rate.load(), static_cast<std::int16_t>(n % 3 - 1), 2);  // +-1 count of noise on y
  };
  GyroTrigger trigger(std::move(twin), "twin", trigger_options());
  const std::int64_t ms = 1'000'000;
  auto r = run_trigger_until(trigger, core::monotonic_now().count() + 300 * ms);  // learning, then rest
  EXPECT_EQ(r.flashes, 0u);
  EXPECT_GT(trigger.samples(), 100u);  // 600 in 300 ms at 0.5 ms on a quiet machine, fewer on a loaded one
  const std::int64_t began = core::realtime_now().ns();
  rate = 30 * 131;  // 30 deg/s about x
  r = run_trigger_until(trigger, core::monotonic_now().count() + 200 * ms);
  EXPECT_EQ(r.flashes, 1u);
  EXPECT_EQ(trigger.onsets(), 1u);
  EXPECT_GT(r.first_flash_ns, began);
  // A few read periods of 0.5 ms and the wake-ups: about 2 ms on a quiet machine. The bound leaves
  // room for a loaded one (a 2-core machine running two builds beside the tests delayed the sampling
  // thread past 20 ms); the detector's own delay is measured on the twin's traces (streaming_test.cpp).
  EXPECT_LT(r.first_flash_ns - began, 100 * ms);
  EXPECT_FALSE(r.ended);
}

TEST(GyroTrigger, AnI2cErrorEndsTheTriggerAndIsReported) {
  auto twin = std::make_unique<RegisterTwin>();
  twin->registers[mpu6050::reg::who_am_i] = 0x68;
  twin->fail_after = 200;  // the configuration's transfers, then some reads
  GyroTrigger trigger(std::move(twin), "twin", trigger_options());
  const auto r = run_trigger_until(trigger, core::monotonic_now().count() + 2'000'000'000);
  EXPECT_TRUE(r.ended);
  ASSERT_EQ(r.refused.size(), 1u);
  EXPECT_NE(r.refused[0].find("gyroscope: "), std::string::npos) << r.refused[0];
  EXPECT_NE(r.refused[0].find("Remote I/O error"), std::string::npos) << r.refused[0];
}

TEST(GyroTrigger, AMissingChipFailsAtOnce) {
  auto twin = std::make_unique<RegisterTwin>();
  twin->absent = true;
  EXPECT_THROW(GyroTrigger trigger(std::move(twin), "twin", trigger_options()), core::Error);
}

}  // namespace
}  // namespace m2mlat::capture
