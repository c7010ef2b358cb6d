// The clock monitor: due times are kept on CLOCK_MONOTONIC_RAW, which no step can move.
#include "m2mlat/sync/clock_monitor.hpp"

#include <utility>

namespace m2mlat::sync {

namespace {

bool state_changed(const KernelClockState& a, const KernelClockState& b) {
  return a.available != b.available || a.synchronised != b.synchronised || a.status != b.status ||
         a.state != b.state || a.tai != b.tai;
}

bool due(const std::optional<std::int64_t>& at, std::int64_t now) { return !at || now >= *at; }

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
  }
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
