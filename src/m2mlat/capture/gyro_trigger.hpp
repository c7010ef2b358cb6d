// The LED switched at the gyroscope's own motion onset (`m2mlat led --on-gyro`): a LedTrigger whose
// sampler (gyro_source.hpp) reads the chip and wakes the trigger after every sample; each sample goes
// through the streaming onset detector (onset/streaming.hpp), and at each onset it finds the trigger
// asks for a flash. The LED's switch is recorded as every switch of `m2mlat led` is (the middle of
// the clock readings around the ioctl); between the sampled onset and the switch lie the detector's
// delay (docs/onset.md: milliseconds, by how fast the motion starts), the wake-up and the ioctl.
//
// An I2C error stops the sampler; the trigger then ends (its error is returned as a refused input,
// so `led` reports it) and the LED is left off.
#pragma once

#include <cstdint>
#include <memory>
#include <string>

#include "m2mlat/capture/gyro_source.hpp"
#include "m2mlat/capture/led_trigger.hpp"
#include "m2mlat/capture/mpu6050.hpp"
#include "m2mlat/capture/register_bus.hpp"
#include "m2mlat/core/fd.hpp"
#include "m2mlat/onset/streaming.hpp"

namespace m2mlat::capture {

struct GyroTriggerOptions {
  core::Duration period{1'000'000};  // between two reads of the chip, ns
  int rt_priority = 0;               // SCHED_FIFO for the sampling thread; 0: leave it
  int cpu = -1;                      // CPU of the sampling thread; -1: leave it
  onset::StreamingOptions detector;
};

class GyroTrigger final : public LedTrigger {
 public:
  // Checks and configures the chip on `bus` (core::Error(io) for a missing or wrong chip) and starts
  // sampling at once: construct it after the process's StopSignal, so that the thread blocks the
  // signals. `name` describes the chip ("/dev/i2c-1 address 0x68").
  GyroTrigger(std::unique_ptr<RegisterBus> bus, std::string name, GyroTriggerOptions options);
  ~GyroTrigger() override;

  int fd() const override { return wake_.get(); }
  bool take(TriggerInput& out) override;
  std::string describe() const override;

  std::uint64_t onsets() const { return onsets_; }
  std::uint64_t samples() const { return samples_; }
  GyroSummary summary() const { return source_->summary(); }
  double threshold_deg_s() const { return detector_.threshold_deg_s(); }

 private:
  std::unique_ptr<RegisterBus> bus_;
  std::unique_ptr<Mpu6050> chip_;
  std::string name_;
  core::Fd wake_;  // eventfd the sampler writes
  std::unique_ptr<GyroSource> source_;
  onset::StreamingDetector detector_;
  std::uint64_t onsets_ = 0, samples_ = 0;
  bool reported_ = false;  // the sampler's end was reported
};

}  // namespace m2mlat::capture
