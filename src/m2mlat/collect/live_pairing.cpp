// Live pairing: re-reads the current scenario and pairs it as `m2mlat stats` does.
#include "m2mlat/collect/live_pairing.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <filesystem>
#include <limits>

#include "m2mlat/analysis/pairing_counts.hpp"
#include "m2mlat/analysis/pipeline.hpp"
#include "m2mlat/analysis/scenario_breakdown.hpp"
#include "m2mlat/analysis/scenario_result.hpp"
#include "m2mlat/analysis/store_chains.hpp"
#include "m2mlat/collect/live_breakdown.hpp"
#include "m2mlat/core/error.hpp"
#include "m2mlat/markers/stored_markers.hpp"
#include "m2mlat/store/store.hpp"

namespace m2mlat::collect {

std::string_view to_string(LiveState state) {
  switch (state) {
    case LiveState::waiting: return "waiting";
    case LiveState::ok: return "ok";
    case LiveState::error: return "error";
  }
  return "?";
}

namespace {

constexpr std::int64_t kMinNs = std::numeric_limits<std::int64_t>::min();
// From the live window's start until its chains are whole: longer than a motion (1.2 s in the twin's
// fastest-to-slowest range) plus the reference detector's re-arming (10,000 still samples, 1.25 s
// at 8 kHz), ns.
constexpr std::int64_t kLoopSettle = 3'000'000'000;

// floor(a / b) for b > 0, also for negative a (latencies may be negative with min_latency < 0).
std::int64_t floor_div(std::int64_t a, std::int64_t b) {
  const auto q = a / b;
  return (a % b != 0 && a < 0) ? q - 1 : q;
}

}  // namespace

std::vector<HistogramBin> histogram(const std::vector<std::int64_t>& latencies_ns, std::size_t max_bins) {
  std::vector<HistogramBin> bins;
  if (latencies_ns.empty() || max_bins == 0) return bins;
  const auto [lo_it, hi_it] = std::minmax_element(latencies_ns.begin(), latencies_ns.end());
  const std::int64_t lo = *lo_it, hi = *hi_it;
  // Widths 1, 2, 5, 10, 20, 50 ... ns: the first whose aligned bins number at most max_bins.
  std::int64_t width = 1;
  constexpr std::array kSteps{1, 2, 5};
  for (std::int64_t decade = 1;; decade *= 10) {
    bool found = false;
    for (auto step : kSteps) {
      width = decade * step;
      const auto first = floor_div(lo, width), last = floor_div(hi, width);
      if (static_cast<std::uint64_t>(last - first) + 1 <= max_bins) {
        found = true;
        break;
      }
    }
    if (found || decade > std::int64_t{100'000'000'000'000'000}) break;
  }
  const auto first = floor_div(lo, width), last = floor_div(hi, width);
  bins.reserve(static_cast<std::size_t>(last - first + 1));
  for (auto k = first; k <= last; ++k) bins.push_back({k * width, (k + 1) * width, 0});
  for (auto v : latencies_ns) ++bins[static_cast<std::size_t>(floor_div(v, width) - first)].count;
  return bins;
}

struct LivePairing::Opened {
  store::Store store;
};

LivePairing::LivePairing(std::string store_path, LiveOptions options)
    : store_path_(std::move(store_path)), options_(std::move(options)) {
  // The median's and the IQR's confidence intervals as `m2mlat stats` gives them by default (2000
  // resamples, seed 1, 95 %): a resample draws only its order statistics, so they cost about 15 ms an
  // update whatever the number of pairs (docs/statistics.md).
  if (!options_.summary.bootstrap) options_.summary.bootstrap = stats::BootstrapOptions{};
  summary_.message = "no store yet";
  if (options_.stages) breakdown_ = std::make_unique<LiveBreakdown>(*options_.stages, options_.stages_window);
}

LivePairing::~LivePairing() = default;

const LiveSummary& LivePairing::update() { return update(false); }

const LiveSummary& LivePairing::finish() { return update(true); }

const LiveSummary& LivePairing::update(bool final) {
  try {
    if (!opened_) {
      if (!std::filesystem::exists(store_path_)) {
        summary_.state = LiveState::waiting;
        summary_.message = fmt::format("{}: no store yet", store_path_);
        return summary_;
      }
      store::Options o;
      o.read_only = true;
      opened_ = std::make_unique<Opened>(Opened{store::Store::open(store_path_, o)});
    }
    const auto last_seq = opened_->store.last_seq();
    const auto sessions = opened_->store.sessions().size();
    std::int64_t rate_samples = 0;  // gyroscope blocks come without events: counted apart
    if (options_.chains)
      for (const auto& c : opened_->store.rate_channels()) rate_samples += c.samples;
    const std::tuple now{last_seq, sessions, rate_samples};
    // Markers come without events (a late pull of the operator's): they alone warrant a new join.
    const bool new_markers = breakdown_ && !final && breakdown_->pull(opened_->store) > 0;
    if (seen_ && *seen_ == now && !new_markers && !(final && breakdown_)) return summary_;
    seen_ = now;
    repair(final);
  } catch (const core::Error& e) {
    // A store being created by another thread may briefly be unreadable: try again next time.
    summary_.state = e.kind() == core::ErrorKind::data ? LiveState::error : LiveState::waiting;
    summary_.message = e.what();
    if (summary_.state == LiveState::waiting) opened_.reset();
  } catch (const std::exception& e) {
    // Anything else (out of memory) must not end the coordinator from the pairing thread.
    summary_.state = LiveState::error;
    summary_.message = e.what();
  }
  return summary_;
}

void LivePairing::repair(bool final) {
  const auto started = std::chrono::steady_clock::now();
  const auto& store = opened_->store;
  LiveSummary s;
  s.store_last_seq = std::get<0>(*seen_);
  s.pairings = summary_.pairings + 1;
  s.scenario = options_.scenario;
  if (s.scenario.empty()) {
    const auto sessions = store.sessions();
    if (sessions.empty()) {
      s.message = "no session yet";
      summary_ = std::move(s);
      return;
    }
    s.scenario = sessions.back().scenario;  // in id order: the newest session's
  }
  if (options_.chains && analysis::has_rate_traces(store, s.scenario)) {
    chain(s);
    s.update_cost_ns =
        std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::steady_clock::now() - started)
            .count();
    summary_ = std::move(s);
    return;
  }
  analysis::ScenarioResult r;
  try {
    analysis::PipelineOptions pipeline;
    pipeline.selection = options_.selection;
    pipeline.match = options_.match;
    pipeline.summary = options_.summary;
    pipeline.include_ambiguous = options_.include_ambiguous;
    r = analysis::analyse_store_scenario(store, s.scenario, pipeline);
  } catch (const core::Error& e) {
    // Until both agents have sent their session, a side is missing: that is waiting, not an error.
    const std::string what = e.what();
    const bool missing_side = what.find("has no ") != std::string::npos;
    s.state = missing_side ? LiveState::waiting : LiveState::error;
    s.message = what;
    summary_ = std::move(s);
    return;
  }
  s.state = LiveState::ok;
  s.cause_ref = r.input.cause_ref;
  s.effect_ref = r.input.effect_ref;
  s.clock = r.input.clock;
  const auto counts = analysis::pairing_counts(r);
  s.cause_events = static_cast<std::int64_t>(counts.cause.edges);
  s.effect_events = static_cast<std::int64_t>(counts.effect.edges);
  s.pairs = counts.pairs;
  s.ambiguous = counts.flagged;
  s.cause_unmatched = counts.cause.unpaired();
  s.effect_unmatched = counts.effect.unpaired();
  s.bounces = counts.bounces();
  s.summary = std::move(r.summary);
  for (const auto& w : r.warnings) s.warnings.push_back(w.text);
  const auto& pairs = r.match.pairs;
  const auto keep = std::min(pairs.size(), options_.recent_samples);
  s.recent.reserve(keep);
  const auto times = r.times();
  const auto sample = [&](const pairing::Pair& p) {
    return LiveSample{times.cause(p), times.latency(p).count(), p.ambiguous()};
  };
  for (auto k = pairs.size() - keep; k < pairs.size(); ++k) s.recent.push_back(sample(pairs[k]));
  if (!pairs.empty()) s.last = sample(pairs.back());
  s.histogram = histogram(r.latencies_ns(), options_.max_histogram_bins);
  if (breakdown_) {
    if (final) {
      // Every marker of the store, as `stats --stages` reads them (all scenarios).
      const auto all = markers::store_markers(store);
      analysis::attach_breakdown(r, breakdown_->rule(), analysis::MarkerIndex(all));
    } else {
      breakdown_->update(r);
    }
    r.breakdown->events.clear();
    r.breakdown->events.shrink_to_fit();
    s.breakdown = std::move(r.breakdown);
  }
  s.update_cost_ns =
      std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::steady_clock::now() - started)
          .count();
  summary_ = std::move(s);
}

void LivePairing::chain(LiveSummary& s) {
  analysis::ChainSelection selection;
  selection.station = options_.selection.cause;
  selection.vehicle = options_.selection.effect;
  selection.photo_edge = options_.selection.edge;
  selection.led_channel = options_.led_channel;
  selection.photo_channel = options_.photo_channel;
  selection.default_led_bound = options_.default_led_bound;
  selection.window = options_.loop_window;
  analysis::StoreChainInput input;
  try {
    input = analysis::chain_input(opened_->store, s.scenario, selection);
  } catch (const core::Error& e) {
    // Until both boards have sent a trace, one is missing: waiting, not an error.
    const std::string what = e.what();
    s.state = what.find("has no ") != std::string::npos ? LiveState::waiting : LiveState::error;
    s.message = what;
    return;
  }
  analysis::ChainOptions options;
  options.detector = options_.detector;
  stats::SummaryOptions summary = options_.summary;
  summary.thresholds.clear();
  const auto r = analysis::build_chains(input.input, options, summary, s.scenario);
  // A chain whose first link lies within kLoopSettle of the window's start may have lost a link (or
  // its onset) to the cut: a motion under way there, or a detector not yet re-armed. It is left out.
  const auto settled = input.window_start_ns ? *input.window_start_ns + kLoopSettle : kMinNs;
  std::vector<const analysis::Chain*> kept;
  for (const auto& c : r.chains) {
    std::int64_t first = std::numeric_limits<std::int64_t>::max();
    for (const auto& t : {c.station_onset_ns, c.vehicle_onset_ns, c.led_ns, c.photo_ns})
      if (t) first = std::min(first, *t);
    if (first >= settled) kept.push_back(&c);
  }
  s.state = LiveState::ok;
  s.cause_ref = {input.station_node, input.station_channel};
  s.effect_ref = {input.vehicle_node, input.vehicle_channel};
  s.clock = input.input.station_trace.clock;
  LiveLoop loop;
  loop.detector = r.detector;
  loop.window_ns = options_.loop_window.count();
  loop.chains = kept.size();
  std::array<std::size_t, analysis::kChainGaps> gaps{};
  for (const auto* c : kept)
    if (c->gap) ++gaps[static_cast<std::size_t>(*c->gap)];
  for (std::size_t k = 0; k < gaps.size(); ++k)
    loop.incomplete.emplace_back(std::string(analysis::key(static_cast<analysis::ChainGap>(k))), gaps[k]);
  loop.warnings = std::move(input.warnings);
  for (std::size_t q = 0; q < loop.quantities.size(); ++q) {
    std::vector<std::int64_t> values, ids;
    for (std::size_t i = 0; i < kept.size(); ++i)
      if (const auto& v = kept[i]->values[q].ns) {
        values.push_back(*v);
        ids.push_back(static_cast<std::int64_t>(i + 1));
      }
    const auto st = stats::summarize(values, ids, summary);
    auto& out = loop.quantities[q];
    out.n = st.n;
    out.median_ms = st.median_ms;
    out.p95_ms = st.p95_ms;
    if (!values.empty()) out.last_ns = values.back();  // the chains are in time order
  }
  s.loop = std::move(loop);
}

}  // namespace m2mlat::collect
