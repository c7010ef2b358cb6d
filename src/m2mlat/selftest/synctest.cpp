// The synchronisation test's analysis (definitions in synctest.hpp).
#include "m2mlat/selftest/synctest.hpp"

#include <algorithm>
#include <cmath>

#include "m2mlat/formats/json_number.hpp"
#include "m2mlat/stats/quantile.hpp"

namespace m2mlat::selftest {

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
using formats::number;


nlohmann::json stats_json(const ValueStats& s) {
  nlohmann::json j{{"n", s.n},
                   {"mean_ns", number(s.mean_ns)},
                   {"sd_ns", number(s.sd_ns)},
                   {"min_ns", number(s.min_ns)},
                   {"max_ns", number(s.max_ns)}};
  auto& p = j["percentiles"] = nlohmann::json::array();
  for (const auto& [percent, value] : s.percentiles)
    p.push_back({{"percent", percent}, {"ns", number(value)}});
  return j;
}

}  // namespace

ValueStats value_stats(std::span<const std::int64_t> values_ns, std::span<const double> percents) {
  ValueStats s;
  s.n = values_ns.size();
  std::vector<std::int64_t> sorted(values_ns.begin(), values_ns.end());
  std::sort(sorted.begin(), sorted.end());
  if (sorted.empty()) {
    s.mean_ns = s.sd_ns = s.min_ns = s.max_ns = kNaN;
  } else {
    // Mean and sd from the offsets relative to the first one: exact integer differences first.
    long double sum = 0;
    for (auto v : sorted) sum += static_cast<long double>(v);
    const long double mean = sum / static_cast<long double>(sorted.size());
    long double ss = 0;
    for (auto v : sorted) ss += (static_cast<long double>(v) - mean) * (static_cast<long double>(v) - mean);
    s.mean_ns = static_cast<double>(mean);
    s.sd_ns = sorted.size() > 1
                  ? static_cast<double>(std::sqrt(ss / static_cast<long double>(sorted.size() - 1)))
                  : kNaN;
    s.min_ns = static_cast<double>(sorted.front());
    s.max_ns = static_cast<double>(sorted.back());
  }
  for (double percent : percents) {
    stats::check_percentile(percent);
    s.percentiles.emplace_back(percent,
                               stats::quantile(std::span<const std::int64_t>(sorted), percent / 100));
  }
  return s;
}

SyncTestResult analyse_offsets(std::vector<OffsetSample> series, const SyncTestOptions& options) {
  SyncTestResult r;
  std::stable_sort(series.begin(), series.end(),
                   [](const auto& a, const auto& b) { return a.t_ns < b.t_ns; });
  r.series = std::move(series);
  std::vector<std::int64_t> offsets, magnitudes, times, jitter, abs_jitter, daemon_error;
  for (const auto& s : r.series) {
    offsets.push_back(s.offset_ns);
    magnitudes.push_back(s.offset_ns < 0 ? -s.offset_ns : s.offset_ns);
    times.push_back(s.t_ns);
    if (s.daemon_offset_ns && s.daemon_bound_ns) {
      ++r.daemon_samples;
      daemon_error.push_back(s.offset_ns - *s.daemon_offset_ns);
      if (*s.daemon_bound_ns != analysis::kUnbounded &&
          (s.offset_ns < 0 ? -s.offset_ns : s.offset_ns) <= *s.daemon_bound_ns)
        ++r.within_daemon_bound;
    }
  }
  for (std::size_t i = 1; i < offsets.size(); ++i) {
    const std::int64_t d = offsets[i] - offsets[i - 1];
    jitter.push_back(d);
    abs_jitter.push_back(d < 0 ? -d : d);
  }
  r.offset = value_stats(offsets, options.percentiles);
  r.abs_offset = value_stats(magnitudes, options.percentiles);
  r.jitter = value_stats(jitter, options.percentiles);
  r.abs_jitter = value_stats(abs_jitter, options.percentiles);
  r.daemon_error = value_stats(daemon_error, options.percentiles);

  r.tau0 = options.tau0.count() > 0 ? options.tau0 : pairing::median_interval(times);
  if (r.tau0.count() > 0) {
    for (std::size_t i = 1; i < times.size(); ++i)
      if (2 * (times[i] - times[i - 1]) > 3 * r.tau0.count()) ++r.gaps;
    // Phase in ns relative to the first offset (differences of integers: exact as doubles).
    std::vector<double> x;
    x.reserve(offsets.size());
    for (auto v : offsets) x.push_back(static_cast<double>(v - offsets.front()));
    const auto factors = stats::octave_factors(x.size(), options.max_factors);
    r.stability = stats::stability(x, r.tau0, factors);
  }
  return r;
}

SyncTestResult synctest_from_edges(std::span<const std::int64_t> a_ns, std::span<const std::int64_t> b_ns,
                                   const analysis::ClockTrack& a_clock, const analysis::ClockTrack& b_clock,
                                   const pairing::PulsePairingOptions& pairing_options,
                                   const SyncTestOptions& options, double growth_ppm) {
  const auto paired = pairing::pair_pulses(a_ns, b_ns, pairing_options);
  std::vector<OffsetSample> series;
  series.reserve(paired.pairs.size());
  for (const auto& p : paired.pairs) {
    OffsetSample s;
    s.t_ns = p.a_ns;
    s.offset_ns = p.offset_ns();
    const auto oa = analysis::offset_at(a_clock, p.a_ns);
    const auto ob = analysis::offset_at(b_clock, p.b_ns);
    if (oa && ob) {
      s.daemon_offset_ns = *ob - *oa;
      const auto ba = analysis::bound_at(a_clock, p.a_ns, growth_ppm);
      const auto bb = analysis::bound_at(b_clock, p.b_ns, growth_ppm);
      s.daemon_bound_ns =
          ba.synchronised && bb.synchronised && ba.max_error_ns <= analysis::kUnbounded - bb.max_error_ns
              ? ba.max_error_ns + bb.max_error_ns
              : analysis::kUnbounded;
    }
    series.push_back(s);
  }
  auto r = analyse_offsets(std::move(series), options);
  r.period = paired.period;
  r.unmatched_a = paired.unmatched_a.size();
  r.unmatched_b = paired.unmatched_b.size();
  return r;
}

SyncTestResult synctest_from_rig(const formats::SyncImport& rig, const SyncTestOptions& options) {
  std::vector<OffsetSample> series;
  series.reserve(rig.samples.size());
  for (const auto& s : rig.samples) series.push_back({s.trigger_time.count(), s.offset_ns, {}, {}});
  return analyse_offsets(std::move(series), options);
}

nlohmann::json synctest_json(const SyncTestResult& r, bool with_series) {
  nlohmann::json j{{"format", kSyncTestFormat},      {"source", r.source},
                   {"pulses", r.series.size()},      {"unmatched_a", r.unmatched_a},
                   {"unmatched_b", r.unmatched_b},   {"period_ns", r.period.count()},
                   {"tau0_ns", r.tau0.count()},      {"gaps", r.gaps},
                   {"offset", stats_json(r.offset)}, {"abs_offset", stats_json(r.abs_offset)},
                   {"jitter", stats_json(r.jitter)}, {"abs_jitter", stats_json(r.abs_jitter)}};
  auto& st = j["stability"] = nlohmann::json::array();
  for (const auto& p : r.stability)
    st.push_back({{"n", p.n},
                  {"tau_s", p.tau_s},
                  {"adev", number(p.adev)},
                  {"mdev", number(p.mdev)},
                  {"tdev_ns", number(p.tdev_ns)},
                  {"mtie_ns", number(p.mtie_ns)},
                  {"adev_terms", p.adev_terms}});
  j["daemon"] = {{"samples", r.daemon_samples},
                 {"measured_minus_estimate", stats_json(r.daemon_error)},
                 {"within_bound", r.within_daemon_bound}};
  if (with_series) {
    auto& series = j["series"] = nlohmann::json::array();
    for (const auto& s : r.series)
      series.push_back(
          {{"t_ns", s.t_ns},
           {"offset_ns", s.offset_ns},
           {"daemon_offset_ns", s.daemon_offset_ns ? nlohmann::json(*s.daemon_offset_ns) : nullptr},
           {"daemon_bound_ns", s.daemon_bound_ns && *s.daemon_bound_ns != analysis::kUnbounded
                                   ? nlohmann::json(*s.daemon_bound_ns)
                                   : nullptr}});
  }
  return j;
}

void write_series_csv(std::ostream& out, const SyncTestResult& r) {
  out << "t_ns,offset_ns,daemon_offset_ns,daemon_bound_ns\n";
  for (const auto& s : r.series) {
    out << s.t_ns << ',' << s.offset_ns << ',';
    if (s.daemon_offset_ns) out << *s.daemon_offset_ns;
    out << ',';
    if (s.daemon_bound_ns && *s.daemon_bound_ns != analysis::kUnbounded) out << *s.daemon_bound_ns;
    out << '\n';
  }
}

}  // namespace m2mlat::selftest
