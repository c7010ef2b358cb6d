// The clock monitor: turns the clock state of this board into store::ClockSample records while
// the recorder runs. It is called with every event batch (RecorderOptions' clock hook) and adds a
// sample only when one is due or the state changed, so that a quiet clock costs one adjtimex call
// (about 1 us) per batch:
//   - "adjtimex": every kernel_interval, and at once when the synchronised flag, the STA_* bits or
//     the TAI offset change;
//   - "step": whenever CLOCK_REALTIME moved against CLOCK_MONOTONIC_RAW by more than the rate
//     correction explains (StepDetector, size known), or, when it did not, the kernel's state went
//     from synchronised to the reset a settimeofday() leaves (STA_UNSYNC, maxerror 16 s): a step of
//     unknown size (store/clock_step.hpp, origin "adjtimex");
//   - "chrony" / "ptp": every chrony_interval / ptp_interval (0 = off) by running chronyc / pmc
//     (a few ms / about 100 ms: keep these intervals long). A failing program adds no sample; its
//     message is kept in last_error() until it works again.
#pragma once

#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "m2mlat/store/records.hpp"
#include "m2mlat/sync/chrony.hpp"
#include "m2mlat/process/command_runner.hpp"
#include "m2mlat/sync/kernel_clock.hpp"
#include "m2mlat/sync/ptp.hpp"
#include "m2mlat/sync/step_detector.hpp"

namespace m2mlat::sync {

// Where the monitor reads the kernel: the real clocks, or a scripted twin in tests.
class ClockSource {
 public:
  virtual ~ClockSource() = default;
  virtual KernelClockState kernel_state() = 0;
  virtual ClockPair clock_pair() = 0;
};

class SystemClockSource final : public ClockSource {
 public:
  KernelClockState kernel_state() override { return read_kernel_clock(); }
  ClockPair clock_pair() override { return read_clock_pair(); }
};

struct MonitorOptions {
  core::Duration kernel_interval = std::chrono::seconds(1);  // an adjtimex sample at least this often
  core::Duration chrony_interval{0};                         // 0: chrony not read
  core::Duration ptp_interval{0};                            // 0: ptp4l not read
  StepOptions step;
  ChronycOptions chronyc;
  PmcOptions pmc;
};

class ClockMonitor {
 public:
  // `runner` runs chronyc/pmc (may be null when both intervals are 0); both must outlive the monitor.
  ClockMonitor(MonitorOptions options, ClockSource& clocks, process::CommandRunner* runner);

  // The recorder's hook: appends to `out` the samples that are due, with session_id = session.
  void on_batch(std::int64_t session, std::vector<store::ClockSample>& out);
  // Every source read now, due or not (for `m2mlat clock` and the start of a session).
  void sample_all(std::int64_t session, std::vector<store::ClockSample>& out);

  // The last failure of chronyc or pmc (empty when the last attempt of each worked).
  const std::string& last_error() const { return last_error_; }
  const std::string& chrony_error() const { return chrony_error_; }
  const std::string& ptp_error() const { return ptp_error_; }
  std::uint64_t steps_detected() const { return steps_; }

 private:
  void read_kernel(std::int64_t session, bool force, std::vector<store::ClockSample>& out);
  void read_chrony(std::int64_t session, std::vector<store::ClockSample>& out);
  void read_ptp(std::int64_t session, std::vector<store::ClockSample>& out);
  void note_error(std::string& slot, const std::string& message);

  MonitorOptions options_;
  ClockSource& clocks_;
  process::CommandRunner* runner_;
  StepDetector steps_detector_;
  std::optional<KernelClockState> last_kernel_;
  std::optional<std::int64_t> kernel_due_raw_ns_, chrony_due_raw_ns_, ptp_due_raw_ns_;
  std::int64_t now_raw_ns_ = 0;  // CLOCK_MONOTONIC_RAW of the current call
  ClockPair now_pair_;
  std::int64_t last_realtime_ns_ = 0;  // CLOCK_REALTIME of the previous reading
  std::string chrony_error_, ptp_error_, last_error_;
  std::uint64_t steps_ = 0;
};

}  // namespace m2mlat::sync
