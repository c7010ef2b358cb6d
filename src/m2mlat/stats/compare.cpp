// Two-sample comparison: point estimates from the sorted samples, intervals from paired bootstrap
// replicates, tests from mann_whitney.cpp and brown_forsythe.cpp.
#include "m2mlat/stats/compare.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "m2mlat/core/error.hpp"
#include "m2mlat/core/random.hpp"
#include "m2mlat/stats/distributions.hpp"
#include "m2mlat/stats/moments.hpp"
#include "m2mlat/stats/quantile.hpp"
#include "m2mlat/stats/rng.hpp"
#include "m2mlat/stats/threshold.hpp"

namespace m2mlat::stats {

namespace {
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kNsPerMs = 1e6;

double sd_ms(std::span<const std::int64_t> values) {
  return sample_sd(values, exact_mean(values)) / kNsPerMs;
}

// Wilson score interval for k successes of n.
Interval wilson(std::size_t k, std::size_t n, double z) {
  const double nn = static_cast<double>(n), p = static_cast<double>(k) / nn, z2 = z * z;
  const double centre = (p + z2 / (2 * nn)) / (1 + z2 / nn);
  const double half = z / (1 + z2 / nn) * std::sqrt(p * (1 - p) / nn + z2 / (4 * nn * nn));
  return {std::max(0.0, centre - half), std::min(1.0, centre + half)};
}

Interval nan_interval() { return {kNaN, kNaN}; }
}  // namespace

Interval newcombe_interval(std::size_t k1, std::size_t n1, std::size_t k2, std::size_t n2, double level) {
  const double z = normal_quantile(0.5 + level / 2);
  const double p1 = static_cast<double>(k1) / static_cast<double>(n1);
  const double p2 = static_cast<double>(k2) / static_cast<double>(n2);
  const auto w1 = wilson(k1, n1, z), w2 = wilson(k2, n2, z);
  const double d = p1 - p2;
  return {d - std::sqrt((p1 - w1.lower) * (p1 - w1.lower) + (w2.upper - p2) * (w2.upper - p2)),
          d + std::sqrt((w1.upper - p1) * (w1.upper - p1) + (p2 - w2.lower) * (p2 - w2.lower))};
}

std::vector<double> bootstrap_sd_ms(std::span<const std::int64_t> sorted_ns, std::size_t resamples,
                                    std::uint64_t seed) {
  std::vector<double> out;
  const auto n = sorted_ns.size();
  if (n < 2 || resamples == 0) return out;
  // Deviations from the floor of the exact mean, in ms: small numbers, so the one-pass sums of a
  // resample lose nothing that matters (relative error ~1e-12 of the variance).
  const auto centre = exact_mean(sorted_ns).floor_ns;
  std::vector<double> d(n);
  for (std::size_t i = 0; i < n; ++i) d[i] = static_cast<double>(sorted_ns[i] - centre) / kNsPerMs;
  out.reserve(resamples);
  const double nn = static_cast<double>(n);
  for (std::size_t b = 0; b < resamples; ++b) {
    IndexStream draw(Rng::stream(seed, b), static_cast<std::uint32_t>(n));
    double s = 0.0, s2 = 0.0;
    for (std::size_t i = 0; i < n; ++i) {
      const double x = d[draw.next()];
      s += x;
      s2 += x * x;
    }
    const double var = (s2 - s * s / nn) / (nn - 1);
    out.push_back(std::sqrt(std::max(0.0, var)));
  }
  return out;
}

Comparison compare(std::span<const std::int64_t> subject_ns, std::span<const std::int64_t> baseline_ns,
                   const CompareOptions& options) {
  return compare(CompareSample{subject_ns, false, {}}, CompareSample{baseline_ns, false, {}}, options);
}

namespace {

// One side's resampled quartiles (ns, resamples x {q1, median, q3}) and SDs (ms), as its plan says.
struct SideReplicates {
  std::vector<double> q1, median, q3, sd_ms;
};
SideReplicates side_replicates(const CompareSample& side, const std::vector<std::int64_t>& sorted,
                               const Resampling& plan, std::size_t resamples, std::uint64_t seed,
                               std::uint64_t sd_seed) {
  SideReplicates out;
  if (!plan.sample_by_sample()) {
    auto r = unit_replicates(side.ns, side.unit_starts, plan, resamples, seed, true);
    return {std::move(r.q1), std::move(r.median), std::move(r.q3), std::move(r.sd_ms)};
  }
  const double probabilities[] = {0.25, 0.5, 0.75};
  const auto q = bootstrap_quantiles(sorted, probabilities, resamples, seed);
  out.q1 = q.column(0);
  out.median = q.column(1);
  out.q3 = q.column(2);
  out.sd_ms = bootstrap_sd_ms(sorted, resamples, sd_seed);
  return out;
}

}  // namespace

Comparison compare(const CompareSample& subject, const CompareSample& baseline, const CompareOptions& options) {
  const auto subject_ns = subject.ns, baseline_ns = baseline.ns;
  check_confidence_level(options.level);
  if (!(options.alpha > 0.0 && options.alpha < 1.0))
    throw core::Error(core::ErrorKind::usage,
                      fmt::format("significance level {} is not in (0, 1)", options.alpha));
  if (subject_ns.size() < 2 || baseline_ns.size() < 2)
    throw core::Error(core::ErrorKind::data,
                      fmt::format("a comparison needs at least 2 latencies on each side ({} has {})",
                                  subject_ns.size() < 2 ? "the subject" : "the baseline",
                                  std::min(subject_ns.size(), baseline_ns.size())));
  if (subject_ns.size() > 0xFFFFFFFFu || baseline_ns.size() > 0xFFFFFFFFu)
    throw core::Error(core::ErrorKind::data, "a comparison takes at most 2^32 - 1 latencies per side");
  std::vector<std::int64_t> s(subject_ns.begin(), subject_ns.end()),
      b(baseline_ns.begin(), baseline_ns.end());
  std::sort(s.begin(), s.end());
  std::sort(b.begin(), b.end());

  Comparison c;
  const auto plan = [](const CompareSample& side) {
    if (side.in_time_order) return plan_resampling(side.ns, side.unit_starts);
    Resampling one_by_one;
    one_by_one.samples = one_by_one.units = side.ns.size();
    return one_by_one;
  };
  c.subject_resampling = plan(subject);
  c.baseline_resampling = plan(baseline);
  c.resamples = options.resamples;
  c.seed = options.seed;
  c.level = options.level;
  c.alpha = options.alpha;
  c.n_subject = s.size();
  c.n_baseline = b.size();
  const auto q = [](const std::vector<std::int64_t>& v, double p) {
    return quantile(std::span<const std::int64_t>(v), p) / kNsPerMs;
  };
  c.median_subject_ms = q(s, 0.5);
  c.median_baseline_ms = q(b, 0.5);
  c.iqr_subject_ms = q(s, 0.75) - q(s, 0.25);
  c.iqr_baseline_ms = q(b, 0.75) - q(b, 0.25);
  c.sd_subject_ms = sd_ms(s);
  c.sd_baseline_ms = sd_ms(b);
  c.median_difference_ms = c.median_subject_ms - c.median_baseline_ms;
  c.iqr_ratio = c.iqr_baseline_ms > 0 ? c.iqr_subject_ms / c.iqr_baseline_ms : kNaN;
  c.sd_ratio = c.sd_baseline_ms > 0 ? c.sd_subject_ms / c.sd_baseline_ms : kNaN;
  c.median_difference_ci_ms = c.iqr_ratio_ci = c.sd_ratio_ci = nan_interval();

  if (options.resamples > 0) {
    SplitMix64 seeds(options.seed);
    const auto seed_s = seeds.next(), seed_b = seeds.next(), sd_seed_s = seeds.next(),
               sd_seed_b = seeds.next();
    const auto rs = side_replicates(subject, s, c.subject_resampling, options.resamples, seed_s, sd_seed_s);
    const auto rb = side_replicates(baseline, b, c.baseline_resampling, options.resamples, seed_b, sd_seed_b);
    std::vector<double> median_diff, iqr_ratio;
    for (std::size_t r = 0; r < options.resamples; ++r) {
      median_diff.push_back((rs.median[r] - rb.median[r]) / kNsPerMs);
      const double iqr_b = rb.q3[r] - rb.q1[r];
      if (iqr_b > 0) iqr_ratio.push_back((rs.q3[r] - rs.q1[r]) / iqr_b);
    }
    c.median_difference_ci_ms = percentile_interval(median_diff, options.level);
    // A resample whose baseline IQR is 0 has no ratio; the interval is over the others, and absent if
    // more than half are missing.
    if (iqr_ratio.size() * 2 > options.resamples)
      c.iqr_ratio_ci = percentile_interval(iqr_ratio, options.level);
    const auto& sds = rs.sd_ms;
    const auto& sdb = rb.sd_ms;
    std::vector<double> sd_ratio;
    for (std::size_t r = 0; r < options.resamples; ++r)
      if (sdb[r] > 0) sd_ratio.push_back(sds[r] / sdb[r]);
    if (sd_ratio.size() * 2 > options.resamples) c.sd_ratio_ci = percentile_interval(sd_ratio, options.level);
  }

  c.mann_whitney = mann_whitney(s, b);
  c.brown_forsythe = brown_forsythe(s, b);

  const auto shares_s = threshold_shares(s, options.thresholds);
  const auto shares_b = threshold_shares(b, options.thresholds);
  for (std::size_t k = 0; k < options.thresholds.size(); ++k) {
    ShareDifference d;
    d.threshold = options.thresholds[k];
    d.count_subject = shares_s[k].count_above;
    d.count_baseline = shares_b[k].count_above;
    d.share_subject = shares_s[k].fraction_above;
    d.share_baseline = shares_b[k].fraction_above;
    d.difference = d.share_subject - d.share_baseline;
    d.ci = newcombe_interval(d.count_subject, s.size(), d.count_baseline, b.size(), options.level);
    c.shares.push_back(d);
  }

  c.uncertainty_ms = options.uncertainty_ms;
  if (options.uncertainty_ms) {
    c.median_difference_below_uncertainty = std::fabs(c.median_difference_ms) < *options.uncertainty_ms;
    c.iqr_difference_below_uncertainty =
        std::fabs(c.iqr_subject_ms - c.iqr_baseline_ms) < *options.uncertainty_ms;
  }
  return c;
}

}  // namespace m2mlat::stats
