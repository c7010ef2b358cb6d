// Chains of the full loop from raw traces and edges (see chains.hpp).
#include "m2mlat/analysis/chains.hpp"

#include <algorithm>
#include <cmath>

#include "m2mlat/onset/detectors.hpp"
#include "m2mlat/sim/full_loop.hpp"

namespace m2mlat::analysis {

namespace {

constexpr std::size_t kM2m = static_cast<std::size_t>(LoopQuantity::m2m);
constexpr std::size_t kG2g = static_cast<std::size_t>(LoopQuantity::g2g);
constexpr std::size_t kE2e = static_cast<std::size_t>(LoopQuantity::e2e);

LoopValue none(LoopExclusion why = LoopExclusion::missing) { return LoopValue{std::nullopt, why}; }

LoopValue difference(const std::optional<std::int64_t>& later, const std::optional<std::int64_t>& earlier,
                     bool ordered) {
  if (!later || !earlier) return none();
  std::int64_t d = 0;
  if (__builtin_sub_overflow(*later, *earlier, &d)) return none(LoopExclusion::overflow);
  if (ordered && d < 0) return none(LoopExclusion::impossible);
  return LoopValue{d, LoopExclusion::missing};
}

double sq(double x) { return x * x; }

// The clock part of the model's u for a difference stamped on two boards, ns; nullopt when unknown.
std::optional<double> sync_u(const ClockTrack& cause, const ClockTrack& effect, std::int64_t cause_ns,
                             std::int64_t effect_ns, const UncertaintyOptions& options) {
  UncertaintyOptions clock_only = options;
  clock_only.kernel_u = core::Duration{0};
  clock_only.kernel_max = core::Duration{0};
  clock_only.calibration_u = core::Duration{0};
  clock_only.calibration_max = core::Duration{0};
  const auto u = pair_uncertainty(cause, effect, cause_ns, effect_ns, clock_only);
  if (!u.bounded()) return std::nullopt;
  return static_cast<double>(u.u_ns);
}

std::int64_t root(double squares) { return std::llround(std::sqrt(squares)); }

// Fills the chain's values and uncertainties from its links.
void evaluate(Chain& c, const ChainInput& in, const ChainResult& r, const ChainOptions& o) {
  auto& v = c.values;
  v[kM2m] = c.m2m_flagged ? none() : difference(c.vehicle_onset_ns, c.station_onset_ns, false);
  v[kG2g] = c.g2g_flagged ? none() : difference(c.photo_ns, c.led_ns, true);
  if (!v[kM2m].ns) {
    v[kE2e] = none(v[kM2m].why);
  } else if (!v[kG2g].ns) {
    v[kE2e] = none(v[kG2g].why);
  } else {
    std::int64_t sum = 0;
    v[kE2e] = __builtin_add_overflow(*v[kM2m].ns, *v[kG2g].ns, &sum) ? none(LoopExclusion::overflow)
                                                                     : LoopValue{sum, LoopExclusion::missing};
  }
  const auto motion = [](const std::optional<std::size_t>& i, const std::vector<onset::Motion>& onsets) {
    if (!i || !onsets[*i].ended) return none();
    return difference(onsets[*i].end_ns, onsets[*i].onset_ns, true);
  };
  v[static_cast<std::size_t>(LoopQuantity::vehicle_motion)] = motion(c.vehicle, r.vehicle_onsets);
  v[static_cast<std::size_t>(LoopQuantity::station_motion)] = motion(c.station, r.station_onsets);
  if (c.vehicle_onset_ns && c.led_ns) c.led_lag_ns = *c.led_ns - *c.vehicle_onset_ns;

  // The uncertainty terms, ns^2.
  double onsets = 0;
  if (c.station) onsets += sq(static_cast<double>(r.station_onsets[*c.station].onset_sd_ns));
  if (c.vehicle) onsets += sq(static_cast<double>(r.vehicle_onsets[*c.vehicle].onset_sd_ns));
  double circuit =
      sq(static_cast<double>(o.uncertainty.kernel_u.count())) + sq(static_cast<double>(o.photo_u.count()));
  if (c.led) circuit += sq(static_cast<double>(in.led[*c.led].bound_ns)) / 3;
  if (v[kM2m].ns)
    if (const auto s = sync_u(in.station_clock, in.vehicle_clock, *c.station_onset_ns, *c.vehicle_onset_ns,
                              o.uncertainty))
      c.u_ns[0] = root(sq(*s) + onsets);
  if (v[kG2g].ns) {
    const auto s = in.single_board
                       ? std::optional<double>(0.0)
                       : sync_u(in.vehicle_clock, in.station_clock, *c.led_ns, *c.photo_ns, o.uncertainty);
    if (s) c.u_ns[1] = root(sq(*s) + circuit);
  }
  if (v[kE2e].ns) c.u_ns[2] = root(onsets + circuit);
}

std::int64_t first_time(const Chain& c) {
  for (const auto& t : {c.station_onset_ns, c.vehicle_onset_ns, c.led_ns, c.photo_ns})
    if (t) return *t;
  return 0;
}

}  // namespace

ChainOptions::ChainOptions() {
  m2m.min_latency = core::Duration{-500'000'000};
  m2m.max_latency = core::Duration{2'000'000'000};
  m2m.refractory = core::Duration{0};  // onsets do not bounce
  g2g.min_latency = core::Duration{0};
  g2g.max_latency = core::Duration{2'000'000'000};
  g2g.refractory = core::Duration{0};
}

std::string_view key(ChainGap gap) {
  constexpr std::array<std::string_view, kChainGaps> kKeys{
      "no_vehicle_onset", "no_station_onset", "no_led",      "no_photo",
      "led_unjoined",     "photo_unmatched",  "flagged_pair"};
  return kKeys.at(static_cast<std::size_t>(gap));
}

ChainResult build_chains(const ChainInput& in, const ChainOptions& o, const stats::SummaryOptions& summary,
                         std::string scenario) {
  const auto& detector = onset::detector(o.detector);
  ChainResult r;
  r.detector = std::string(detector.name);
  const bool motions = !in.station_trace.samples.empty() || !in.vehicle_trace.samples.empty();
  if (motions) {
    r.station_onsets = detector.detect(in.station_trace).motions;
    r.vehicle_onsets = detector.detect(in.vehicle_trace).motions;
  }
  const auto clock = in.station_trace.clock;
  const auto onset_times = [](const std::vector<onset::Motion>& m) {
    std::vector<std::int64_t> t;
    for (const auto& x : m) t.push_back(x.onset_ns);
    return t;
  };
  const auto station_ns = onset_times(r.station_onsets), vehicle_ns = onset_times(r.vehicle_onsets);
  std::vector<std::int64_t> led_ns;
  for (const auto& l : in.led) led_ns.push_back(l.stamp_ns);
  const auto m2m = pairing::match(station_ns, vehicle_ns, clock, o.m2m);
  const auto g2g = pairing::match(led_ns, in.photo_ns, clock, o.g2g);

  // LED -> photo edge, by LED index.
  std::vector<std::optional<std::size_t>> photo_of(in.led.size());
  std::vector<bool> photo_used(in.photo_ns.size(), false), g2g_flagged(in.led.size(), false);
  for (const auto& p : g2g.pairs) {
    photo_of[static_cast<std::size_t>(p.cause_index)] = static_cast<std::size_t>(p.effect_index);
    g2g_flagged[static_cast<std::size_t>(p.cause_index)] = p.ambiguous();
    photo_used[static_cast<std::size_t>(p.effect_index)] = true;
  }
  // Vehicle onset -> LED write: the first unused write in the join window (both in time order).
  std::vector<std::optional<std::size_t>> led_of(vehicle_ns.size());
  std::vector<bool> led_used(in.led.size(), false);
  std::size_t next = 0;
  for (std::size_t j = 0; j < vehicle_ns.size(); ++j) {
    while (next < led_ns.size() && led_ns[next] < vehicle_ns[j] - o.join_before.count()) ++next;
    if (next < led_ns.size() && led_ns[next] <= vehicle_ns[j] + o.join_after.count()) {
      led_of[j] = next;
      led_used[next++] = true;
    }
  }

  std::vector<Chain> chains;
  auto add_vehicle_links = [&](Chain& c, std::size_t j) {
    c.vehicle = j;
    c.vehicle_onset_ns = vehicle_ns[j];
    if (!led_of[j]) return;
    c.led = led_of[j];
    c.led_ns = led_ns[*c.led];
    if (photo_of[*c.led]) {
      c.photo = photo_of[*c.led];
      c.photo_ns = in.photo_ns[*c.photo];
      c.g2g_flagged = g2g_flagged[*c.led];
    }
  };
  std::vector<bool> vehicle_used(vehicle_ns.size(), false);
  for (const auto& p : m2m.pairs) {
    Chain c;
    c.station = static_cast<std::size_t>(p.cause_index);
    c.station_onset_ns = station_ns[*c.station];
    c.m2m_flagged = p.ambiguous();
    add_vehicle_links(c, static_cast<std::size_t>(p.effect_index));
    vehicle_used[*c.vehicle] = true;
    chains.push_back(c);
  }
  std::vector<bool> station_used(station_ns.size(), false);
  for (const auto& p : m2m.pairs) station_used[static_cast<std::size_t>(p.cause_index)] = true;
  for (std::size_t i = 0; i < station_ns.size(); ++i)
    if (!station_used[i]) {
      Chain c;
      c.station = i;
      c.station_onset_ns = station_ns[i];
      chains.push_back(c);
    }
  for (std::size_t j = 0; j < vehicle_ns.size(); ++j)
    if (!vehicle_used[j]) {
      Chain c;
      add_vehicle_links(c, j);
      chains.push_back(c);
    }
  for (std::size_t i = 0; i < in.led.size(); ++i)
    if (!led_used[i]) {
      Chain c;
      c.led = i;
      c.led_ns = led_ns[i];
      if (photo_of[i]) {
        c.photo = photo_of[i];
        c.photo_ns = in.photo_ns[*c.photo];
        c.g2g_flagged = g2g_flagged[i];
      }
      chains.push_back(c);
    }
  for (std::size_t k = 0; k < in.photo_ns.size(); ++k)
    if (!photo_used[k]) {
      Chain c;
      c.photo = k;
      c.photo_ns = in.photo_ns[k];
      chains.push_back(c);
    }
  std::stable_sort(chains.begin(), chains.end(),
                   [](const Chain& a, const Chain& b) { return first_time(a) < first_time(b); });

  // The first missing link of each chain; without motions (one board, LED on a schedule) the chain is
  // LED -> photo alone.
  for (auto& c : chains) {
    if (motions && c.station && !c.vehicle)
      c.gap = ChainGap::no_vehicle_onset;
    else if (motions && c.vehicle && !c.station)
      c.gap = ChainGap::no_station_onset;
    else if (motions && c.vehicle && !c.led)
      c.gap = ChainGap::no_led;
    else if (motions && c.led && !c.vehicle)
      c.gap = ChainGap::led_unjoined;
    else if (c.led && !c.photo)
      c.gap = ChainGap::no_photo;
    else if (c.photo && !c.led)
      c.gap = ChainGap::photo_unmatched;
    else if (c.m2m_flagged || c.g2g_flagged)
      c.gap = ChainGap::flagged_pair;
    if (c.gap) ++r.incomplete[static_cast<std::size_t>(*c.gap)];
    evaluate(c, in, r, o);
  }
  r.chains = std::move(chains);

  // The summaries, as for the full-loop rig's files; the sample ids are the chains' numbers (from 1).
  auto& loop = r.loop;
  loop.scenario = std::move(scenario);
  loop.file = "chains (" + r.detector + ")";
  loop.from_chains = true;
  loop.events = r.chains.size();
  for (std::size_t k = 0; k < kChainGaps; ++k)
    loop.incomplete.emplace_back(std::string(key(static_cast<ChainGap>(k))), r.incomplete[k]);
  for (std::size_t q = 0; q < kLoopQuantities.size(); ++q) {
    const auto quantity = kLoopQuantities[q];
    if (!motions && quantity != LoopQuantity::g2g) continue;  // G2G alone, as the camera file
    auto& series = loop.quantities[q].emplace();
    for (std::size_t i = 0; i < r.chains.size(); ++i) {
      const auto& value = r.chains[i].values[q];
      if (value.ns) {
        series.ns.push_back(*value.ns);
        series.lines.push_back(static_cast<std::int64_t>(i + 1));
      } else {
        ++series.excluded.at(static_cast<std::size_t>(value.why));
      }
    }
    series.summary = stats::summarize(series.ns, series.lines, options_for(quantity, summary));
  }
  return r;
}

ChainInput chain_input(const sim::FullLoopRun& run) {
  ChainInput in;
  in.station_trace = run.station_trace;
  in.vehicle_trace = run.vehicle_trace;
  in.single_board = run.config.single_board;
  for (const auto& m : run.manoeuvres) {
    in.led.push_back({m.led_stamp_ns, m.led_bound_ns});
    in.photo_ns.push_back(m.photo_stamp_ns);
  }
  // Each board's clock samples, one a second over the run: what a daemon that knows its bound reports.
  const auto samples = [&](bool station) {
    std::vector<store::ClockSample> s;
    for (const auto& b : sim::board_clock_samples(run, station)) {
      store::ClockSample c;
      c.time = core::TimePoint::from_ns(core::Clock::simulated, b.time_ns);
      c.source = "sim";
      c.max_error_ns = b.max_error_ns;
      c.est_error_ns = b.est_error_ns;
      c.synchronised = true;
      s.push_back(c);
    }
    return s;
  };
  in.station_clock = make_clock_track(samples(true), core::Clock::simulated);
  in.vehicle_clock = make_clock_track(samples(false), core::Clock::simulated);
  if (in.station_trace.samples.empty()) in.station_trace.clock = core::Clock::simulated;
  return in;
}

}  // namespace m2mlat::analysis
