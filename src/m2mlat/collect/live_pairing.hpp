// Live pairing: the latency statistics of a campaign store while `m2mlat collect` is filling it.
//
// Every update() re-reads the current scenario from the store and pairs ALL of its events with the
// same code as `m2mlat stats` (analysis::analyse_store_scenario: clock steps corrected), so the live numbers
// on a finished store are exactly the offline ones, and at every moment those of the store as it is.
// Re-pairing everything is cheap while a live session is small (docs/dashboard.md: ~1.4 ms of CPU for
// 1k events, ~90 ms for 100k; linear) and needs no stitching of windows; a test checks that pairs
// well behind the newest edge do not change as the store grows. The caller paces updates by their
// cost (LiveView). Nothing is re-paired while the store has no new event or session.
//
// One LivePairing owns its own read-only store::Store, so it must be used by one thread at a time
// (a Store is per thread). The store may not exist yet when it is made: update() then says so.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

#include "m2mlat/analysis/breakdown.hpp"
#include "m2mlat/analysis/chains.hpp"
#include "m2mlat/analysis/selection.hpp"
#include "m2mlat/analysis/stage_rule.hpp"
#include "m2mlat/pairing/matcher.hpp"
#include "m2mlat/stats/summary.hpp"

namespace m2mlat::collect {

struct LiveOptions {
  analysis::Selection selection;        // cause and effect channels, edges (as `m2mlat stats`)
  pairing::MatchOptions match;          // the matcher's window, refractory, tolerance
  stats::SummaryOptions summary;        // thresholds, extra percentiles, bootstrap (unset: stats' default)
  bool include_ambiguous = false;       // statistics over ambiguous pairs too
  std::string scenario;                 // empty: the scenario of the store's newest session
  std::size_t recent_samples = 300;     // samples kept for the strip chart (the newest)
  std::size_t max_histogram_bins = 40;  // the bin width is the smallest 1/2/5 x 10^k ns that fits
  // A scenario with gyroscope traces is the full loop: its chains (analysis/store_chains.hpp, the
  // selection's cause/effect as station/vehicle, its edge for the photo edges) over the last
  // `loop_window` of the traces, recomputed whole each update: the cost per update is bounded by the
  // window (at 8 kHz, 1 min is ~0.5M samples per board), not by the campaign's length.
  bool chains = true;
  std::string detector = "flank";
  std::string led_channel = "led", photo_channel = "photo";
  core::Duration default_led_bound{100'000};  // an LED write's half-width where its session has none, ns
  core::Duration loop_window{60'000'000'000};
  // With a stage rule (`collect --stages FILE`): each pair joined to the markers collected so far
  // (live_breakdown.hpp); a pair's join is redone while the newest data is less than
  // `stages_window` past its effect: longer than the pullers' lag between boards (a poll, a
  // reconnection: seconds), short enough that an update redoes only the last seconds' pairs.
  std::optional<analysis::StageRule> stages;
  core::Duration stages_window{30'000'000'000};
};

// One quantity of the full loop over the window: count, median, P95 and the newest chain's value.
struct LiveLoopQuantity {
  std::size_t n = 0;
  double median_ms = 0, p95_ms = 0;  // NaN for n = 0
  std::optional<std::int64_t> last_ns;
};
// The full loop's live figures: M2M, G2G, E2E (by analysis::LoopQuantity m2m, g2g, e2e).
struct LiveLoop {
  std::string detector;
  std::int64_t window_ns = 0;
  std::size_t chains = 0;  // complete or not
  std::array<LiveLoopQuantity, 3> quantities;
  std::vector<std::pair<std::string, std::size_t>> incomplete;  // by gap key (chains.hpp)
  std::vector<std::string> warnings;                            // e.g. no LED writes yet
};

// One latency sample for the strip chart.
struct LiveSample {
  std::int64_t cause_ns = 0;    // the cause edge's time, ns on the scenario's clock
  std::int64_t latency_ns = 0;  // effect - cause, ns
  bool ambiguous = false;       // left out of the statistics unless include_ambiguous
  friend bool operator==(const LiveSample&, const LiveSample&) = default;
};

// [lower_ns, upper_ns) holds `count` latencies of the statistics' sample.
struct HistogramBin {
  std::int64_t lower_ns = 0;
  std::int64_t upper_ns = 0;
  std::size_t count = 0;
  friend bool operator==(const HistogramBin&, const HistogramBin&) = default;
};

enum class LiveState : std::uint8_t {
  waiting,  // no store, no session, or one side has no session yet: `message` says which
  ok,       // paired (possibly zero pairs so far)
  error,    // the store or the selection is wrong (e.g. two cause nodes): `message` says why
};
std::string_view to_string(LiveState state);

struct LiveSummary {
  LiveState state = LiveState::waiting;
  std::string message;
  std::string scenario;
  core::ChannelRef cause_ref, effect_ref;
  core::Clock clock = core::Clock::realtime;
  std::int64_t cause_events = 0;  // edges of the selection on each side
  std::int64_t effect_events = 0;
  std::size_t pairs = 0;                // all pairs found, ambiguous or not
  std::size_t ambiguous = 0;            // of them flagged ambiguous
  std::size_t cause_unmatched = 0;      // without partner, bounces not counted
  std::size_t effect_unmatched = 0;     // without partner, bounces not counted
  std::size_t bounces = 0;              // both sides
  stats::Summary summary;               // over the pairs the statistics use (summary.n = samples)
  std::optional<LiveSample> last;       // the newest pair (by cause time), ambiguous or not
  std::vector<LiveSample> recent;       // the newest pairs, oldest first, at most recent_samples
  std::vector<HistogramBin> histogram;  // of the statistics' latencies, contiguous bins
  std::optional<LiveLoop> loop;         // set for a scenario with gyroscope traces (then no pairs)
  std::vector<std::string> warnings;    // the sanity verdict's (analysis/sanity.hpp), with their evidence
  // With a stage rule: the breakdown of the pairs in the statistics (its per-event rows left out:
  // the summary is copied at every refresh; complete + incomplete counts them).
  std::optional<analysis::Breakdown> breakdown;
  std::int64_t store_last_seq = 0;      // the store's last seq when this was computed
  std::int64_t update_cost_ns = 0;      // wall time of the last re-pairing, ns (0 if none ran)
  std::uint64_t pairings = 0;           // re-pairings run so far
};

// Bins of width 1, 2 or 5 x 10^k ns (the smallest giving at most max_bins bins), aligned on
// multiples of the width so the bins stay put as samples arrive. Empty for no latencies.
std::vector<HistogramBin> histogram(const std::vector<std::int64_t>& latencies_ns, std::size_t max_bins);

class LivePairing {
 public:
  LivePairing(std::string store_path, LiveOptions options);
  ~LivePairing();
  LivePairing(const LivePairing&) = delete;
  LivePairing& operator=(const LivePairing&) = delete;

  // Re-pairs if the store changed since the last call (new events or sessions), else returns the
  // previous result. Never throws for store or data problems: they become state waiting or error.
  const LiveSummary& update();
  // The last update: re-pairs, and joins the breakdown with every marker of the store as
  // `stats --stages` does (no frozen joins), so the final figures are the offline ones.
  const LiveSummary& finish();
  const LiveSummary& current() const { return summary_; }
  const LiveOptions& options() const { return options_; }

 private:
  struct Opened;
  const LiveSummary& update(bool final);
  // final: the breakdown from every marker of the store (finish), not the live join.
  void repair(bool final);
  void chain(LiveSummary& s);
  std::string store_path_;
  LiveOptions options_;
  std::unique_ptr<Opened> opened_;
  LiveSummary summary_;
  std::unique_ptr<class LiveBreakdown> breakdown_;  // with options_.stages
  // Last seq, session count and raw rate samples (all channels) when last paired.
  std::optional<std::tuple<std::int64_t, std::size_t, std::int64_t>> seen_;
};

}  // namespace m2mlat::collect
