// Numbering, the keep window and blocks of the gyroscope channel (see gyro_channel.hpp).
#include "m2mlat/capture/gyro_channel.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <limits>
#include <utility>

#include "m2mlat/core/error.hpp"
#include "m2mlat/core/number.hpp"
#include "m2mlat/onset/detectors.hpp"
#include "m2mlat/store/rate_block.hpp"

namespace m2mlat::capture {

GyroKeep parse_gyro_keep(std::string_view flag, std::string_view text) {
  if (text == "all") return {};
  if (text.starts_with("window:")) {
    std::int64_t ms = 0;
    if (core::parse_integer(text.substr(7), ms) && ms > 0 && ms <= 3'600'000)
      return {core::Duration{ms * 1'000'000}};
  }
  throw core::Error(
      core::ErrorKind::usage,
      fmt::format("{}: '{}' is not 'all' or 'window:<ms>' (a positive number of milliseconds)", flag, text));
}

GyroChannel::GyroChannel(std::string channel, core::Clock clock, double counts_per_deg_s, GyroKeep keep)
    : channel_(std::move(channel)), clock_(clock), counts_per_deg_s_(counts_per_deg_s), keep_(keep) {}

void GyroChannel::add(std::vector<core::RateSample> samples, const GyroSummary& summary) {
  const std::uint64_t next = pending_first_ + pending_.size();  // the number the first new sample gets
  pending_.insert(pending_.end(), samples.begin(), samples.end());
  counters_.read += samples.size();
  // The sampler's counts only grow: what grew since the last call is new, numbered from where the
  // next sample would have been.
  const auto lost = [&](std::uint64_t total, std::uint64_t& seen, std::string_view kind) {
    if (total <= seen) return;
    new_losses_.push_back(
        {0, channel_, core::TimePoint{}, next + samples.size(), total - seen, std::string(kind)});
    seen = total;
  };
  lost(summary.missed_periods, counters_.missed_periods, "missed_period");
  lost(summary.i2c_errors, counters_.i2c_errors, "i2c_error");
}

void GyroChannel::emit(std::int64_t session_id, std::size_t from, std::size_t to,
                       std::vector<store::RateBlock>& blocks) {
  if (from >= to) return;
  const std::span<const core::RateSample> run(pending_.data() + from, to - from);
  for (auto& block :
       store::rate_block::split(session_id, channel_, clock_, counts_per_deg_s_, run, pending_first_ + from))
    blocks.push_back(std::move(block));
  counters_.stored += to - from;
}

void GyroChannel::collect(const RawRound& round, core::TimePoint now, std::vector<store::RateBlock>& blocks,
                          std::vector<store::Loss>& losses) {
  constexpr std::int64_t kNever = std::numeric_limits<std::int64_t>::max();
  for (auto& loss : new_losses_) {
    if (round.session_id == 0) break;  // no session to hold them: kept for the next one
    loss.session_id = round.session_id;
    loss.detected_at = now;
    losses.push_back(std::move(loss));
  }
  if (round.session_id != 0) new_losses_.clear();

  // Samples stamped before the session began (all of them while none is open) are no session's.
  const std::int64_t start = round.session_id == 0 ? kNever : round.session_start.ns();
  std::size_t i = static_cast<std::size_t>(decided_ - pending_first_);
  const std::size_t first_undecided = i;
  while (i < pending_.size() && pending_[i].time_ns < start) ++i;
  counters_.outside_session += i - first_undecided;
  decided_ = pending_first_ + i;
  if (pending_.empty()) return;

  const std::int64_t window = keep_.window.count();
  const std::int64_t newest = pending_.back().time_ns;
  std::int64_t decide_to = window == 0 ? kNever : newest - window - kDecisionDelay.count();
  if (round.end) decide_to = round.end->ns();
  if (round.final) decide_to = kNever;

  if (window == 0) {  // all: every sample up to decide_to is stored, and nothing decided is kept
    std::size_t j = i;
    while (j < pending_.size() && pending_[j].time_ns <= decide_to) ++j;
    emit(round.session_id, i, j, blocks);
    decided_ = pending_first_ + j;
    pending_.erase(pending_.begin(), pending_.begin() + static_cast<std::ptrdiff_t>(j));
    pending_first_ = decided_;
    return;
  }

  // Keep window: the detector over what is in memory gives the intervals to keep.
  core::RateTrace trace{clock_, counts_per_deg_s_, pending_};
  const auto detection = onset::detector("flank").detect(trace);
  std::vector<std::pair<std::int64_t, std::int64_t>> keep;  // [from, to] ns
  for (const auto& m : detection.motions)
    keep.emplace_back(m.onset_ns - window, m.ended ? m.end_ns + window : kNever);
  // The samples in memory begin in a motion only at the sampler's start (history is never cut
  // inside a motion, below): its onset was before the recording; keep up to the first onset seen.
  if (detection.began_in_motion)
    keep.emplace_back(std::numeric_limits<std::int64_t>::min(),
                      detection.motions.empty() ? kNever : detection.motions.front().onset_ns);
  const auto kept = [&](std::int64_t t) {
    return std::any_of(keep.begin(), keep.end(), [t](const auto& k) { return t >= k.first && t <= k.second; });
  };

  while (i < pending_.size() && pending_[i].time_ns <= decide_to) {
    const bool in = kept(pending_[i].time_ns);
    std::size_t j = i;
    while (j < pending_.size() && pending_[j].time_ns <= decide_to && kept(pending_[j].time_ns) == in) ++j;
    if (in)
      emit(round.session_id, i, j, blocks);
    else
      counters_.left_out += j - i;
    i = j;
  }
  decided_ = pending_first_ + i;

  // Forget decided samples older than the detector's history, but never cut into a motion or the
  // history after it: the detector must see each motion whole, from the rest before it, or it would
  // take a motion's tail for the start of the trace.
  const std::int64_t decided_to = i < pending_.size() ? pending_[i].time_ns : newest;
  std::int64_t forget_before = decided_to - kDetectorHistory.count();
  for (const auto& m : detection.motions) {
    const std::int64_t after = m.ended ? m.end_ns + window + kDetectorHistory.count() : kNever;
    if (forget_before > m.onset_ns - window && forget_before <= after) forget_before = m.onset_ns - window;
  }
  std::size_t drop = 0;
  while (drop < i && pending_[drop].time_ns < forget_before) ++drop;
  if (round.final) drop = pending_.size();
  pending_.erase(pending_.begin(), pending_.begin() + static_cast<std::ptrdiff_t>(drop));
  pending_first_ += drop;
}

}  // namespace m2mlat::capture
