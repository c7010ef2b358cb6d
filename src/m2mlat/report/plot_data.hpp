// The numbers behind every figure, computed once from a report for the HTML charts and for the
// pgfplots files alike. Statistics (box, histogram counts) are over every sample; only what is
// drawn point by point is thinned: the ECDF to at most kEcdfPoints steps, the latency-over-time
// series to kSeriesPoints bins (min, median, max per bin) when longer, the clock series by stride.
#pragma once

#include <cstddef>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "m2mlat/report/report_model.hpp"
#include "m2mlat/stats/bootstrap.hpp"

namespace m2mlat::report {

inline constexpr std::size_t kEcdfPoints = 400;
inline constexpr std::size_t kSeriesPoints = 1500;
inline constexpr std::size_t kClockPoints = 800;
inline constexpr std::size_t kMaxOutliersDrawn = 100;  // per side of a box

// Tukey box plot: whiskers reach the most extreme samples within 1.5 IQR of the box.
struct BoxData {
  std::string scenario, group;
  std::size_t n = 0;
  double q1 = 0, median = 0, q3 = 0, whisker_low = 0, whisker_high = 0;  // ms
  std::vector<double> outliers;   // ms; the most extreme ones when there are many
  std::size_t outlier_count = 0;  // all of them
  std::optional<stats::Interval> median_ci;  // ms: the median's bootstrap confidence interval, if computed
};
BoxData box_data(const ScenarioReport& scenario);
// The same of any sample (ns, sorted ascending), named `name` in group `group`.
BoxData box_of(std::span<const std::int64_t> sorted_ns, std::string name, std::string group);

// ECDF steps: (latency ms, fraction of samples <= it), at most kEcdfPoints of them, the first and
// last sample included.
struct Curve {
  std::vector<double> x, y;
};
Curve ecdf_data(const ScenarioReport& scenario);

// Histograms over common bins (edges in ms) so that scenarios can be overlaid.
struct Histograms {
  std::vector<double> edges;                     // bins + 1 edges
  std::vector<std::vector<std::size_t>> counts;  // per scenario, per bin
};
Histograms histogram_data(const Report& report, std::size_t bins = 40);

// Latency over time: x = seconds since the scenario's first cause edge. Either every pair (with its
// uncertainty when known) or, for long series, bins of pairs with min / median / max and the largest
// uncertainty in the bin.
struct TimeSeries {
  bool binned = false;
  std::vector<double> t_s, latency_ms, low_ms, high_ms;  // low/high: latency -/+ uncertainty, or bin min/max
  std::vector<double> uncertainty_ms;                    // per point (NaN: unknown)
  std::size_t samples = 0;                               // pairs behind the series
};
TimeSeries time_series(const ScenarioReport& scenario);

// One board's clock over a scenario, thinned by stride: x = seconds since the scenario's first cause
// edge (or the first sample), offset and bound in ms.
struct ClockCurve {
  std::string node, source;
  std::vector<double> t_s, offset_ms, bound_ms;
  std::size_t samples = 0;
};
std::vector<ClockCurve> clock_curves(const ScenarioReport& scenario);

// A scenario name as a file-name part: letters, digits, '-' and '_' kept, anything else '_'.
std::string file_part(const std::string& name);

}  // namespace m2mlat::report
