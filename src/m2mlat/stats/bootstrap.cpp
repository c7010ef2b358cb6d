// Resampled quantiles of a sorted sample from their order statistics' draws, and percentile
// intervals.
#include "m2mlat/stats/bootstrap.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <functional>

#include "m2mlat/core/error.hpp"
#include "m2mlat/stats/order_statistics.hpp"
#include "m2mlat/stats/quantile.hpp"
#include "m2mlat/stats/rng.hpp"

namespace m2mlat::stats {

void check_confidence_level(double level) {
  if (!(level > 0.0 && level < 1.0)) {
    throw core::Error(core::ErrorKind::usage, fmt::format("confidence level {} is outside (0, 1)", level));
  }
}

std::vector<double> BootstrapQuantiles::column(std::size_t k) const {
  std::vector<double> out(resamples);
  for (std::size_t b = 0; b < resamples; ++b) out[b] = value(b, k);
  return out;
}

BootstrapQuantiles bootstrap_quantiles(std::span<const std::int64_t> sorted_ns,
                                       std::span<const double> probabilities, std::size_t resamples,
                                       std::uint64_t seed) {
  const std::size_t n = sorted_ns.size();
  if (n == 0) throw core::Error(core::ErrorKind::internal, "bootstrap_quantiles: empty sample");
  if (!std::is_sorted(sorted_ns.begin(), sorted_ns.end())) {
    throw core::Error(core::ErrorKind::internal, "bootstrap_quantiles: the sample is not sorted");
  }

  // The order statistics (0-based ranks within a resample) the quantiles interpolate between.
  std::vector<QuantilePosition> positions;
  std::vector<std::size_t> wanted;
  for (const double p : probabilities) {
    const QuantilePosition at = quantile_position(n, p);
    positions.push_back(at);
    wanted.push_back(at.lower);
    if (at.fraction != 0.0) wanted.push_back(at.lower + 1);
  }
  std::sort(wanted.begin(), wanted.end());
  wanted.erase(std::unique(wanted.begin(), wanted.end()), wanted.end());
  const auto slot = [&](std::size_t rank) {
    return static_cast<std::size_t>(std::lower_bound(wanted.begin(), wanted.end(), rank) - wanted.begin());
  };

  BootstrapQuantiles out;
  out.probabilities.assign(probabilities.begin(), probabilities.end());
  out.resamples = resamples;
  out.values.resize(resamples * probabilities.size());
  std::vector<std::size_t> ranks(wanted.size());
  for (std::size_t b = 0; b < resamples; ++b) {
    Rng rng = Rng::stream(seed, b);
    resample_order_statistics(rng, n, wanted, ranks);
    for (std::size_t k = 0; k < positions.size(); ++k) {
      const QuantilePosition& at = positions[k];
      const std::int64_t low = sorted_ns[ranks[slot(at.lower)]];
      out.values[b * positions.size() + k] =
          at.fraction == 0.0 ? static_cast<double>(low)
                             : interpolate(low, sorted_ns[ranks[slot(at.lower + 1)]], at.fraction);
    }
  }
  return out;
}

Interval percentile_interval(std::span<const double> replicates, double level) {
  check_confidence_level(level);
  if (replicates.empty()) throw core::Error(core::ErrorKind::internal, "percentile_interval: no replicates");
  std::vector<double> sorted(replicates.begin(), replicates.end());
  std::sort(sorted.begin(), sorted.end());
  return {quantile(std::span<const double>(sorted), (1.0 - level) / 2.0),
          quantile(std::span<const double>(sorted), (1.0 + level) / 2.0)};
}

namespace {

// The intervals from the resamples' medians and IQRs (ns).
MedianIqrCi median_iqr_ci(std::span<const double> medians, std::span<const double> iqrs,
                          const BootstrapOptions& options) {
  const auto to_ms = [](Interval i) { return Interval{i.lower / 1e6, i.upper / 1e6}; };
  MedianIqrCi ci;
  ci.median_ms = to_ms(percentile_interval(medians, options.level));
  ci.iqr_ms = to_ms(percentile_interval(iqrs, options.level));
  ci.resamples = options.resamples;
  ci.seed = options.seed;
  ci.level = options.level;
  return ci;
}

// A sample's value and the unit it came in, sorted by value for the resamples' walk.
struct Labelled {
  std::int64_t ns = 0;
  std::uint32_t unit = 0;
};

// The median and IQR intervals from the units' replicates.
MedianIqrCi resample_units(std::span<const std::int64_t> in_time_order, std::span<const std::size_t> starts,
                           const Resampling& plan, const BootstrapOptions& options) {
  const UnitReplicates r = unit_replicates(in_time_order, starts, plan, options.resamples, options.seed, false);
  std::vector<double> iqrs(options.resamples);
  for (std::size_t b = 0; b < options.resamples; ++b) iqrs[b] = r.q3[b] - r.q1[b];
  return median_iqr_ci(r.median, iqrs, options);
}

}  // namespace

UnitReplicates unit_replicates(std::span<const std::int64_t> in_time_order, std::span<const std::size_t> starts,
                               const Resampling& plan, std::size_t resamples, std::uint64_t seed, bool with_sd) {
  const std::size_t units = plan.units;
  std::vector<std::uint32_t> size(units);
  std::vector<Labelled> sorted(in_time_order.size());
  for (std::size_t u = 0; u < units; ++u) {
    const std::size_t begin = starts.empty() ? u : starts[u];
    const std::size_t end = starts.empty() ? u + 1 : (u + 1 < units ? starts[u + 1] : in_time_order.size());
    size[u] = static_cast<std::uint32_t>(end - begin);
    for (std::size_t i = begin; i < end; ++i) sorted[i] = {in_time_order[i], static_cast<std::uint32_t>(u)};
  }
  std::sort(sorted.begin(), sorted.end(), [](const Labelled& a, const Labelled& b) {
    return a.ns != b.ns ? a.ns < b.ns : a.unit < b.unit;
  });
  // Deviations from the sample's middle value, in ms: small numbers for the SD's one-pass sums.
  const std::int64_t centre = sorted.empty() ? 0 : sorted[sorted.size() / 2].ns;

  UnitReplicates out;
  out.q1.resize(resamples);
  out.median.resize(resamples);
  out.q3.resize(resamples);
  if (with_sd) out.sd_ms.resize(resamples);
  const std::size_t block = plan.blocks.length;
  std::vector<std::uint32_t> weight(units);
  for (std::size_t b = 0; b < resamples; ++b) {
    std::fill(weight.begin(), weight.end(), 0u);
    IndexStream draw(Rng::stream(seed, b), static_cast<std::uint32_t>(units));
    std::size_t n = 0;
    for (std::size_t taken = 0; taken < units;) {
      std::size_t u = draw.next();
      for (std::size_t j = 0; j < block && taken < units; ++j, ++taken) {
        ++weight[u];
        n += size[u];
        if (++u == units) u = 0;
      }
    }
    // The order statistics (0-based ranks in the resample) the three quartiles interpolate between.
    const QuantilePosition at[] = {quantile_position(n, 0.25), quantile_position(n, 0.5), quantile_position(n, 0.75)};
    std::size_t rank[6];
    for (std::size_t k = 0; k < 3; ++k) {
      rank[2 * k] = at[k].lower;
      rank[2 * k + 1] = std::min(at[k].lower + 1, n - 1);
    }
    std::int64_t value[6] = {};
    std::size_t next = 0, below = 0;  // ranks found; resample values at or below the walk
    double s = 0, s2 = 0;            // the resample's sums of deviations (ms) and their squares
    for (std::size_t i = 0; i < sorted.size() && (with_sd || next < 6); ++i) {
      const std::uint32_t w = weight[sorted[i].unit];
      below += w;
      while (next < 6 && rank[next] < below) value[next++] = sorted[i].ns;
      if (with_sd && w != 0) {
        const double d = static_cast<double>(sorted[i].ns - centre) / 1e6;
        s += w * d;
        s2 += w * d * d;
      }
    }
    double q[3];
    for (std::size_t k = 0; k < 3; ++k)
      q[k] = at[k].fraction == 0.0 ? static_cast<double>(value[2 * k])
                                   : interpolate(value[2 * k], value[2 * k + 1], at[k].fraction);
    out.q1[b] = q[0];
    out.median[b] = q[1];
    out.q3[b] = q[2];
    if (with_sd) {
      const double nn = static_cast<double>(n);
      out.sd_ms[b] = n > 1 ? std::sqrt(std::max(0.0, (s2 - s * s / nn) / (nn - 1))) : 0.0;
    }
  }
  return out;
}

std::optional<MedianIqrCi> bootstrap_median_iqr(std::span<const std::int64_t> sorted_ns,
                                                const BootstrapOptions& options) {
  check_confidence_level(options.level);
  if (sorted_ns.empty() || options.resamples == 0) return std::nullopt;
  const double probabilities[] = {0.25, 0.5, 0.75};
  const BootstrapQuantiles q = bootstrap_quantiles(sorted_ns, probabilities, options.resamples, options.seed);
  std::vector<double> medians(q.resamples), iqrs(q.resamples);
  for (std::size_t b = 0; b < q.resamples; ++b) {
    medians[b] = q.value(b, 1);
    iqrs[b] = q.value(b, 2) - q.value(b, 0);
  }
  MedianIqrCi ci = median_iqr_ci(medians, iqrs, options);
  ci.resampling.samples = ci.resampling.units = sorted_ns.size();
  return ci;
}

Resampling plan_resampling(std::span<const std::int64_t> in_time_order, std::span<const std::size_t> unit_starts) {
  const std::size_t n = in_time_order.size();
  if (!unit_starts.empty() && (unit_starts.front() != 0 || unit_starts.back() >= n ||
                               std::adjacent_find(unit_starts.begin(), unit_starts.end(),
                                                  std::greater_equal<>()) != unit_starts.end())) {
    throw core::Error(core::ErrorKind::internal, "plan_resampling: unit starts not ascending within the sample");
  }
  Resampling plan;
  plan.samples = n;
  plan.units = unit_starts.empty() ? n : unit_starts.size();
  const auto begin = [&](std::size_t u) { return unit_starts.empty() ? u : unit_starts[u]; };
  const auto end = [&](std::size_t u) { return u + 1 < plan.units ? begin(u + 1) : n; };
  for (std::size_t u = 0; u < plan.units; ++u) plan.largest_unit = std::max(plan.largest_unit, end(u) - begin(u));

  // The ranks of the units' mean latencies over the stretches the dependence is estimated from.
  const std::vector<Stretch> stretches = estimation_stretches(plan.units);
  std::vector<std::vector<double>> series;
  std::vector<double> all;
  for (const Stretch s : stretches) {
    auto& means = series.emplace_back();
    for (std::size_t u = s.begin; u < s.end; ++u) {
      double sum = 0;
      for (std::size_t i = begin(u); i < end(u); ++i) sum += static_cast<double>(in_time_order[i]);
      means.push_back(sum / static_cast<double>(end(u) - begin(u)));
    }
    all.insert(all.end(), means.begin(), means.end());
  }
  std::sort(all.begin(), all.end());
  for (auto& means : series)
    for (double& x : means) {
      const auto [lo, hi] = std::equal_range(all.begin(), all.end(), x);
      x = static_cast<double>((lo - all.begin()) + (hi - all.begin()) - 1) / 2.0;  // mid-rank of ties
    }
  plan.blocks = block_length(series, plan.units);
  plan.over_limit = n > kMaxUnitResampled && (plan.grouped() || plan.blocks.length > 1);
  return plan;
}

std::optional<MedianIqrCi> resample_median_iqr(std::span<const std::int64_t> in_time_order,
                                               std::span<const std::size_t> unit_starts, const Resampling& plan,
                                               const BootstrapOptions& options) {
  check_confidence_level(options.level);
  if (in_time_order.empty() || options.resamples == 0) return std::nullopt;
  MedianIqrCi ci;
  if (plan.sample_by_sample()) {
    std::vector<std::int64_t> sorted(in_time_order.begin(), in_time_order.end());
    std::sort(sorted.begin(), sorted.end());
    ci = *bootstrap_median_iqr(sorted, options);
  } else {
    ci = resample_units(in_time_order, unit_starts, plan, options);
  }
  ci.resampling = plan;
  return ci;
}

}  // namespace m2mlat::stats
