// Clock step detection. CLOCK_MONOTONIC_RAW follows the oscillator and is never adjusted;
// CLOCK_REALTIME is slewed (by the frequency correction) and stepped (settimeofday, chrony's
// makestep, phc2sys). Between two readings, realtime - raw may change by what the rate correction
// explains (elapsed * ppm) and a little more; a change beyond that by more than a threshold
// (default 1 ms) is a step, recorded as a clock sample with source "step" and detail
// {from_ns, to_ns, step_ns}.
#pragma once

#include <cstdint>
#include <optional>

#include "m2mlat/core/time.hpp"
#include "m2mlat/store/records.hpp"
#include "m2mlat/sync/kernel_clock.hpp"

namespace m2mlat::sync {

struct StepOptions {
  core::Duration threshold = std::chrono::milliseconds(1);  // unexplained change that counts as a step
  double tolerance_ppm = 500;  // rate beyond the kernel's correction still not a step: the kernel's
                               // PLL may slew up to 500 ppm on top of the frequency (MAXPHASE/MAXFREQ)
};

struct Step {
  std::int64_t from_ns = 0;         // CLOCK_REALTIME now had the clock only run at its corrected rate, ns
  std::int64_t to_ns = 0;           // CLOCK_REALTIME as read, ns
  std::int64_t step_ns = 0;         // to - from, ns (positive = the clock jumped forward)
  std::int64_t unexplained_ns = 0;  // |step| less what the rates allow, ns (> threshold)
  std::int64_t explained_ns = 0;    // what the rates and pairing windows allow: the bound on the size's error, ns
  std::int64_t elapsed_ns = 0;      // CLOCK_MONOTONIC_RAW between the two readings: the step lies somewhere in it, ns
};

class StepDetector {
 public:
  explicit StepDetector(StepOptions options = {}) : options_(options) {}
  // One reading: the clock pair and the rate correction in force (ppm, KernelClockState::rate_ppm).
  // Returns the step since the previous reading, if there was one.
  std::optional<Step> observe(const ClockPair& pair, double rate_ppm);
  void reset() { last_.reset(); }

 private:
  struct Last {
    ClockPair pair;
    double rate_ppm = 0;
  };
  StepOptions options_;
  std::optional<Last> last_;
};

// The step as a clock sample (source "step", store/clock_step.hpp, origin "monitor") at the time of
// the reading: size step_ns known to within explained_ns (standard uncertainty half of that); it
// happened between the two readings, so at a reading of the new timescale in
// [to_ns - elapsed_ns - explained_ns, to_ns].
store::ClockSample step_sample(const Step& step);

}  // namespace m2mlat::sync
