// Figure data from the report's samples.
#include "m2mlat/report/plot_data.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <limits>

#include "m2mlat/stats/quantile.hpp"

namespace m2mlat::report {

namespace {
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
double ms(std::int64_t ns) { return static_cast<double>(ns) / 1e6; }

std::vector<std::int64_t> sorted_latencies(const ScenarioReport& s) {
  auto v = s.result.latencies_ns();
  std::sort(v.begin(), v.end());
  return v;
}

// The pairs in the statistics, with their index into match.pairs.
std::vector<std::size_t> used_pairs(const ScenarioReport& s) {
  std::vector<std::size_t> out;
  const auto& pairs = s.result.match.pairs;
  for (std::size_t i = 0; i < pairs.size(); ++i)
    if (s.result.include_ambiguous || !pairs[i].ambiguous()) out.push_back(i);
  return out;
}

std::int64_t origin_ns(const ScenarioReport& s) {
  const auto& pairs = s.result.match.pairs;
  if (!pairs.empty()) return s.result.times().cause(pairs.front());
  if (!s.result.input.cause.t_ns.empty()) return s.result.input.cause.t_ns.front();
  return 0;
}
}  // namespace

BoxData box_data(const ScenarioReport& s) {
  const auto v = sorted_latencies(s);
  auto box = box_of(v, s.result.input.scenario, s.group);
  if (const auto& ci = s.result.summary.bootstrap) box.median_ci = ci->median_ms;
  return box;
}

BoxData box_of(std::span<const std::int64_t> v, std::string name, std::string group) {
  BoxData b;
  b.scenario = std::move(name);
  b.group = std::move(group);
  b.n = v.size();
  if (v.empty()) return b;
  b.q1 = stats::quantile(v, 0.25) / 1e6;
  b.median = stats::quantile(v, 0.5) / 1e6;
  b.q3 = stats::quantile(v, 0.75) / 1e6;
  const double lo_fence = b.q1 - 1.5 * (b.q3 - b.q1), hi_fence = b.q3 + 1.5 * (b.q3 - b.q1);
  std::size_t first = 0, last = v.size() - 1;
  while (first < last && ms(v[first]) < lo_fence) ++first;
  while (last > first && ms(v[last]) > hi_fence) --last;
  b.whisker_low = ms(v[first]);
  b.whisker_high = ms(v[last]);
  b.outlier_count = first + (v.size() - 1 - last);
  // The most extreme outliers on each side, at most kMaxOutliersDrawn each.
  for (std::size_t i = 0; i < std::min(first, kMaxOutliersDrawn); ++i) b.outliers.push_back(ms(v[i]));
  for (std::size_t i = 0; i < std::min(v.size() - 1 - last, kMaxOutliersDrawn); ++i)
    b.outliers.push_back(ms(v[v.size() - 1 - i]));
  return b;
}

Curve ecdf_data(const ScenarioReport& s) {
  Curve c;
  const auto v = sorted_latencies(s);
  const auto n = v.size();
  if (n == 0) return c;
  const std::size_t points = std::min(n, kEcdfPoints);
  for (std::size_t k = 0; k < points; ++k) {
    // Evenly spaced ranks, the last sample included; ties collapse to the last rank of their value.
    std::size_t i = points == 1 ? n - 1 : k * (n - 1) / (points - 1);
    while (i + 1 < n && v[i + 1] == v[i]) ++i;
    if (!c.x.empty() && c.x.back() == ms(v[i])) continue;
    c.x.push_back(ms(v[i]));
    c.y.push_back(static_cast<double>(i + 1) / static_cast<double>(n));
  }
  return c;
}

Histograms histogram_data(const Report& report, std::size_t bins) {
  Histograms h;
  double lo = std::numeric_limits<double>::infinity(), hi = -lo;
  for (const auto& s : report.scenarios)
    if (s.result.summary.min) {
      lo = std::min(lo, s.result.summary.min->ms());
      hi = std::max(hi, s.result.summary.max->ms());
    }
  if (!(hi >= lo)) return h;
  if (hi == lo) hi = lo + 1;
  const double width = (hi - lo) / static_cast<double>(bins);
  for (std::size_t k = 0; k <= bins; ++k) h.edges.push_back(lo + width * static_cast<double>(k));
  for (const auto& s : report.scenarios) {
    auto& c = h.counts.emplace_back(bins, 0);
    for (auto ns : s.result.latencies_ns()) {
      auto k = static_cast<std::size_t>((ms(ns) - lo) / width);
      c[std::min(k, bins - 1)]++;
    }
  }
  return h;
}

TimeSeries time_series(const ScenarioReport& s) {
  TimeSeries ts;
  const auto used = used_pairs(s);
  ts.samples = used.size();
  const auto origin = origin_ns(s);
  const auto& pairs = s.result.match.pairs;
  const auto times = s.result.times();
  const auto unc = [&](std::size_t i) {
    return i < s.uncertainty_ns.size() && s.uncertainty_ns[i] ? ms(*s.uncertainty_ns[i]) : kNaN;
  };
  if (used.size() <= kSeriesPoints) {
    for (auto i : used) {
      const double lat = ms(times.latency(pairs[i]).count()), u = unc(i);
      ts.t_s.push_back(static_cast<double>(times.cause(pairs[i]) - origin) / 1e9);
      ts.latency_ms.push_back(lat);
      ts.uncertainty_ms.push_back(u);
      ts.low_ms.push_back(std::isnan(u) ? lat : lat - u);
      ts.high_ms.push_back(std::isnan(u) ? lat : lat + u);
    }
    return ts;
  }
  ts.binned = true;
  const std::size_t per_bin = (used.size() + kSeriesPoints - 1) / kSeriesPoints;
  std::vector<std::int64_t> bin;
  for (std::size_t start = 0; start < used.size(); start += per_bin) {
    const std::size_t end = std::min(used.size(), start + per_bin);
    bin.clear();
    double u_max = kNaN;
    for (std::size_t k = start; k < end; ++k) {
      bin.push_back(times.latency(pairs[used[k]]).count());
      const double u = unc(used[k]);
      if (!std::isnan(u)) u_max = std::isnan(u_max) ? u : std::max(u_max, u);
    }
    std::sort(bin.begin(), bin.end());
    const auto mid = times.cause(pairs[used[(start + end - 1) / 2]]);
    ts.t_s.push_back(static_cast<double>(mid - origin) / 1e9);
    ts.latency_ms.push_back(stats::quantile(std::span<const std::int64_t>(bin), 0.5) / 1e6);
    ts.low_ms.push_back(ms(bin.front()));
    ts.high_ms.push_back(ms(bin.back()));
    ts.uncertainty_ms.push_back(u_max);
  }
  return ts;
}

std::vector<ClockCurve> clock_curves(const ScenarioReport& s) {
  std::vector<ClockCurve> out;
  std::int64_t origin = origin_ns(s);
  if (s.result.match.pairs.empty() && s.result.input.cause.t_ns.empty() && !s.result.clocks.empty() &&
      !s.result.clocks.front().t_ns.empty())
    origin = s.result.clocks.front().t_ns.front();
  for (const auto& c : s.result.clocks) {
    ClockCurve cc{c.node, c.source, {}, {}, {}, c.t_ns.size()};
    const std::size_t stride = std::max<std::size_t>(1, (c.t_ns.size() + kClockPoints - 1) / kClockPoints);
    for (std::size_t i = 0; i < c.t_ns.size(); i += stride) {
      cc.t_s.push_back(static_cast<double>(c.t_ns[i] - origin) / 1e9);
      cc.offset_ms.push_back(ms(c.offset_ns[i]));
      cc.bound_ms.push_back(ms(c.max_error_ns[i]));
    }
    out.push_back(std::move(cc));
  }
  return out;
}

std::string file_part(const std::string& name) {
  std::string out;
  for (unsigned char ch : name)
    out += (std::isalnum(ch) || ch == '-' || ch == '_') ? static_cast<char>(ch) : '_';
  return out.empty() ? "scenario" : out;
}

}  // namespace m2mlat::report
