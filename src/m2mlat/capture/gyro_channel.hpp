// The gyroscope as a channel of the recorder: the samples its sampler took become blocks of raw rate
// samples (store::RateBlock) for the open session, numbered in read order, and the sampler's missed
// periods and I2C errors become losses, all committed with the recorder's next round.
//
// What is kept: every sample ("all", the default), or only those within a window around each motion
// ("window:<ms>"): the "flank" onset detector (onset/detectors.hpp) runs over the recent samples, and
// a sample is kept if it lies in [onset - window, end + window] of a motion (to the trace's end for a
// motion still going). The window is a storage saving: inside it nothing is dropped, so an onset
// within it can be recomputed later with any detector. A sample is decided once it is older than the
// newest by window + kDecisionDelay (the time the detector may need to see a slow onset), so up to
// that much (at 8 kHz, ~3 s: 24,000 samples) waits in memory; the last round decides everything.
// Samples left out show in the stored blocks as a jump of first_index.
//
// Sessions (the agent begins and ends them while the sampler runs): a sample is stored in the session
// it was sampled in; a block never crosses a session's end (raw_round.hpp). Numbers go on across
// sessions, so a session's first block need not start at 0.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "m2mlat/capture/gyro_source.hpp"
#include "m2mlat/capture/raw_round.hpp"
#include "m2mlat/core/rate_sample.hpp"
#include "m2mlat/core/time.hpp"
#include "m2mlat/store/records.hpp"

namespace m2mlat::capture {

struct GyroKeep {
  core::Duration window{0};  // 0: keep every sample; else keep this much around each motion, ns
};
// "all" or "window:<ms>" (a positive whole number of milliseconds); core::Error(usage) naming `flag`.
GyroKeep parse_gyro_keep(std::string_view flag, std::string_view text);

// How long after a sample the detector may still find a motion whose window holds it, beyond the
// window itself: a slow onset crosses the detector's threshold up to a few hundred ms after its true
// start; 2 s leaves room (ns).
inline constexpr core::Duration kDecisionDelay{2'000'000'000};
// How much decided history the detector keeps before undecided samples, so that it sees the rest
// level before an onset (ns).
inline constexpr core::Duration kDetectorHistory{1'000'000'000};

struct GyroChannelCounters {
  std::uint64_t read = 0;      // samples the sampler took
  std::uint64_t stored = 0;    // samples put into blocks
  std::uint64_t left_out = 0;  // samples outside every window (keep window only)
  std::uint64_t outside_session = 0;  // sampled while no session was open: not stored
  std::uint64_t missed_periods = 0;
  std::uint64_t i2c_errors = 0;
};

class GyroChannel {
 public:
  GyroChannel(std::string channel, core::Clock clock, double counts_per_deg_s, GyroKeep keep);

  // Takes the samples the sampler read since the last call (oldest first) and its counts so far.
  void add(std::vector<core::RateSample> samples, const GyroSummary& summary);
  // Moves the decided samples into blocks for the round's session and the new losses (detected at
  // `now`) into `losses`. Samples stamped before the session's start (or while none is open) are
  // no session's: counted as outside_session, not stored. With the round's end set, every sample
  // stamped up to it is decided now (the window detector sees what it has so far), later ones wait.
  // `final`: the sampler has stopped; decide everything.
  void collect(const RawRound& round, core::TimePoint now, std::vector<store::RateBlock>& blocks,
               std::vector<store::Loss>& losses);

  // The newest sample's stamp taken so far (none yet: nullopt), ns.
  std::optional<std::int64_t> newest_ns() const {
    return pending_.empty() ? std::nullopt : std::optional(pending_.back().time_ns);
  }
  const std::string& channel() const { return channel_; }
  const GyroChannelCounters& counters() const { return counters_; }

 private:
  void emit(std::int64_t session_id, std::size_t from, std::size_t to, std::vector<store::RateBlock>& blocks);

  std::string channel_;
  core::Clock clock_;
  double counts_per_deg_s_;
  GyroKeep keep_;
  // Samples not yet dropped from memory: pending_[i] is sample number pending_first_ + i. Those
  // numbered below decided_ are decided (stored or left out) and kept only as the detector's history.
  std::vector<core::RateSample> pending_;
  std::uint64_t pending_first_ = 0;
  std::uint64_t decided_ = 0;
  GyroChannelCounters counters_;
  std::vector<store::Loss> new_losses_;  // session_id set by collect
};

}  // namespace m2mlat::capture
