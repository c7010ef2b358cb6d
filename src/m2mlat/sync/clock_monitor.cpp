// The clock monitor: due times are kept on CLOCK_MONOTONIC_RAW, which no step can move.
#include "m2mlat/sync/clock_monitor.hpp"

#include <utility>

#include "m2mlat/store/clock_step.hpp"

namespace m2mlat::sync {

namespace {

bool state_changed(const KernelClockState& a, const KernelClockState& b) {
  return a.available != b.available || a.synchronised != b.synchronised || a.status != b.status ||
         a.state != b.state || a.tai != b.tai;
}

bool due(const std::optional<std::int64_t>& at, std::int64_t now) { return !at || now >= *at; }

// The kernel's ntp_clear(), which a settimeofday() runs, sets STA_UNSYNC and resets maxerror and
// esterror to NTP_PHASE_LIMIT (16 s). A clock that was synchronised and now shows that reset was
// set from outside: a step whose size the adjtimex state does not tell.
constexpr std::int64_t kPhaseLimitNs = 16'000'000'000;
bool looks_reset(const KernelClockState& before, const KernelClockState& now) {
  return before.available && now.available && before.synchronised && !now.synchronised &&
         now.max_error_ns >= kPhaseLimitNs && before.max_error_ns < kPhaseLimitNs;
}

}  // namespace

ClockMonitor::ClockMonitor(MonitorOptions options, ClockSource& clocks, process::CommandRunner* runner)
    : options_(std::move(options)), clocks_(clocks), runner_(runner), steps_detector_(options_.step) {}

void ClockMonitor::on_batch(std::int64_t session, std::vector<store::ClockSample>& out) {
  now_pair_ = clocks_.clock_pair();
  now_raw_ns_ = now_pair_.monotonic_raw_ns;
  read_kernel(session, false, out);
  if (options_.chrony_interval.count() > 0 && runner_ && due(chrony_due_raw_ns_, now_raw_ns_))
    read_chrony(session, out);
  if (options_.ptp_interval.count() > 0 && runner_ && due(ptp_due_raw_ns_, now_raw_ns_))
    read_ptp(session, out);
}

void ClockMonitor::sample_all(std::int64_t session, std::vector<store::ClockSample>& out) {
  now_pair_ = clocks_.clock_pair();
  now_raw_ns_ = now_pair_.monotonic_raw_ns;
  read_kernel(session, true, out);
  if (options_.chrony_interval.count() > 0 && runner_) read_chrony(session, out);
  if (options_.ptp_interval.count() > 0 && runner_) read_ptp(session, out);
}

void ClockMonitor::read_kernel(std::int64_t session, bool force, std::vector<store::ClockSample>& out) {
  const KernelClockState state = clocks_.kernel_state();
  if (const auto step = steps_detector_.observe(now_pair_, state.available ? state.rate_ppm() : 0.0)) {
    auto sample = step_sample(*step);
    sample.session_id = session;
    out.push_back(std::move(sample));
    ++steps_;
  } else if (last_kernel_ && looks_reset(*last_kernel_, state)) {
    // No size seen against CLOCK_MONOTONIC_RAW (below the threshold, or the clock was set back to
    // about where it was), but the kernel's state says it was set: a step of unknown size since
    // the previous reading.
    store::ClockStep unknown;
    unknown.at_ns = now_pair_.realtime_ns;
    unknown.earliest_ns = last_realtime_ns_;  // the previous reading (last_kernel_ is set)
    unknown.origin = "adjtimex";
    auto sample = store::step_clock_sample(unknown);
    sample.session_id = session;
    out.push_back(std::move(sample));
    ++steps_;
  }
  last_realtime_ns_ = now_pair_.realtime_ns;
  const bool changed = !last_kernel_ || state_changed(*last_kernel_, state);
  if (force || changed || due(kernel_due_raw_ns_, now_raw_ns_)) {
    auto sample =
        adjtimex_sample(state, core::TimePoint::from_ns(core::Clock::realtime, now_pair_.realtime_ns));
    sample.session_id = session;
    out.push_back(std::move(sample));
    kernel_due_raw_ns_ = now_raw_ns_ + options_.kernel_interval.count();
  }
  last_kernel_ = state;
}

void ClockMonitor::note_error(std::string& slot, const std::string& message) {
  slot = message;
  last_error_ = !chrony_error_.empty() ? chrony_error_ : ptp_error_;
}

void ClockMonitor::read_chrony(std::int64_t session, std::vector<store::ClockSample>& out) {
  chrony_due_raw_ns_ = now_raw_ns_ + options_.chrony_interval.count();
  try {
    const ChronyReport report = sync::read_chrony(*runner_, options_.chronyc);
    auto sample =
        chrony_sample(report, core::TimePoint::from_ns(core::Clock::realtime, now_pair_.realtime_ns));
    sample.session_id = session;
    out.push_back(std::move(sample));
    note_error(chrony_error_, {});
  } catch (const core::Error& e) {
    note_error(chrony_error_, e.what());
  }
}

void ClockMonitor::read_ptp(std::int64_t session, std::vector<store::ClockSample>& out) {
  ptp_due_raw_ns_ = now_raw_ns_ + options_.ptp_interval.count();
  try {
    const PtpStatus status = sync::read_ptp(*runner_, options_.pmc);
    auto sample = ptp_sample(status, core::TimePoint::from_ns(core::Clock::realtime, now_pair_.realtime_ns));
    sample.session_id = session;
    out.push_back(std::move(sample));
    note_error(ptp_error_, {});
  } catch (const core::Error& e) {
    note_error(ptp_error_, e.what());
  }
}

}  // namespace m2mlat::sync
