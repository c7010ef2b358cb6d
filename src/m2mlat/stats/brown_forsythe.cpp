// Brown-Forsythe W. Deviations are taken in ns as doubles after the median is found on the exact
// integers; latencies of ~1e9 ns have deviations far below 2^53, so nothing is lost.
#include "m2mlat/stats/brown_forsythe.hpp"

#include <algorithm>
#include <cmath>

#include "m2mlat/stats/distributions.hpp"
#include "m2mlat/stats/quantile.hpp"

namespace m2mlat::stats {

BrownForsythe brown_forsythe(std::span<const std::span<const std::int64_t>> groups_ns) {
  std::vector<std::vector<double>> z;
  for (const auto& g : groups_ns) {
    if (g.empty()) continue;
    std::vector<std::int64_t> sorted(g.begin(), g.end());
    std::sort(sorted.begin(), sorted.end());
    const double median = quantile(std::span<const std::int64_t>(sorted), 0.5);
    auto& zi = z.emplace_back();
    zi.reserve(sorted.size());
    for (const auto v : sorted) zi.push_back(std::fabs(static_cast<double>(v) - median));
  }
  BrownForsythe r;
  const auto k = z.size();
  std::size_t total = 0;
  for (const auto& zi : z) total += zi.size();
  if (k < 2 || total <= k) return r;
  r.df1 = static_cast<double>(k - 1);
  r.df2 = static_cast<double>(total - k);

  std::vector<double> means;
  double grand = 0.0;
  for (const auto& zi : z) {
    double s = 0.0;
    for (const auto v : zi) s += v;
    means.push_back(s / static_cast<double>(zi.size()));
    grand += s;
  }
  grand /= static_cast<double>(total);
  double between = 0.0, within = 0.0;
  for (std::size_t i = 0; i < k; ++i) {
    const double d = means[i] - grand;
    between += static_cast<double>(z[i].size()) * d * d;
    for (const auto v : z[i]) within += (v - means[i]) * (v - means[i]);
  }
  if (!(within > 0.0)) return r;
  r.w = r.df2 / r.df1 * between / within;
  r.p = fisher_f_sf(r.w, r.df1, r.df2);
  return r;
}

BrownForsythe brown_forsythe(std::span<const std::int64_t> a_ns, std::span<const std::int64_t> b_ns) {
  const std::span<const std::int64_t> groups[] = {a_ns, b_ns};
  return brown_forsythe(std::span<const std::span<const std::int64_t>>(groups));
}

}  // namespace m2mlat::stats
