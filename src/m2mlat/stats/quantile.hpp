// Quantiles of a sorted sample by linear interpolation between order statistics (Hyndman and Fan
// 1996, definition 7: the default of numpy.percentile, R's quantile() and Excel's PERCENTILE.INC).
//
// For n sorted values x[0..n-1] and a probability p in [0, 1], the position is h = (n - 1) p,
// split into j = floor(h) and g = h - j; the quantile is x[j] + g (x[j+1] - x[j]) (x[n-1] when
// j = n - 1). p = 0 gives the minimum, p = 1 the maximum, p = 0.5 the usual median. The
// interpolation is done as numpy does it, so results agree with numpy to the last bit or two.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

namespace m2mlat::stats {

// Where a quantile falls among n sorted values: between index `lower` and lower + 1 (or at
// lower = n - 1), `fraction` of the way. n > 0, p in [0, 1].
struct QuantilePosition {
  std::size_t lower = 0;
  double fraction = 0.0;  // in [0, 1)
};
QuantilePosition quantile_position(std::size_t n, double p);

// Throw core::Error(usage) unless 0 <= p <= 1, or 0 <= percent <= 100 (NaN fails): the values
// often come from the command line ("--percentile 99.9"), so the message quotes them.
void check_probability(double p);
void check_percentile(double percent);

// a + t (b - a), computed as numpy's _lerp does: from b's side when t >= 0.5, so that t = 1
// gives b exactly and the result is monotone in t.
double interpolate(double a, double b, double t);
// The same between two integers a <= b, with b - a taken exactly in integers (as numpy does for
// int64 arrays) before it meets the floating-point weight.
double interpolate(std::int64_t a, std::int64_t b, double t);

// Type-7 quantile of `sorted` (ascending; not checked) at probability p in [0, 1]. The result is
// in the unit of the values (ns in, ns out). NaN for an empty sample. The difference of two
// neighbours is taken in integers, as numpy does for int64 arrays, so it is exact.
double quantile(std::span<const std::int64_t> sorted, double p);
double quantile(std::span<const double> sorted, double p);

// The type-7 median of an unsorted sample (taken by value and sorted here); NaN when empty.
double median(std::vector<std::int64_t> values);

}  // namespace m2mlat::stats
