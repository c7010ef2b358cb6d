// Clock steps from a kernel log's realtime and printk stamps (rules in kernel_log_steps.hpp).
#include "m2mlat/analysis/kernel_log_steps.hpp"

#include <algorithm>
#include <cmath>
#include <cstdlib>

namespace m2mlat::analysis {

namespace {

std::int64_t median_of(std::vector<std::int64_t> v) {
  const auto mid = v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2);
  std::nth_element(v.begin(), mid, v.end());
  if (v.size() % 2 == 1) return *mid;
  const auto low = *std::max_element(v.begin(), mid);
  return low + (*mid - low) / 2;
}

std::int64_t slew(double ppm, std::int64_t span_ns) {
  return static_cast<std::int64_t>(std::ceil(ppm * 1e-6 * static_cast<double>(std::llabs(span_ns))));
}

}  // namespace

std::vector<store::ClockStep> kernel_log_steps(std::span<const std::int64_t> realtime_ns,
                                               std::span<const std::int64_t> log_time_us,
                                               const KernelLogStepOptions& options) {
  std::vector<store::ClockStep> steps;
  const std::size_t n = std::min(realtime_ns.size(), log_time_us.size());
  if (n < 2) return steps;
  std::vector<std::int64_t> d(n), mono(n);
  for (std::size_t i = 0; i < n; ++i) {
    mono[i] = log_time_us[i] * 1000;
    d[i] = realtime_ns[i] - mono[i];
  }
  std::vector<std::int64_t> jumps;
  jumps.reserve(n);
  for (std::size_t i = 1; i < n; ++i)
    if (mono[i] >= mono[i - 1]) jumps.push_back(std::llabs(d[i] - d[i - 1]));
  if (jumps.empty()) return steps;
  const std::int64_t jitter = median_of(jumps);
  // Stamps that do not follow the realtime ones (written by a script, lines of another clock) are no
  // clock to compare with: a typical jump beyond the smallest step, or jumps at more than one line
  // in 20, and nothing is said.
  if (jitter > options.threshold_ns) return steps;
  const std::int64_t threshold = std::max(options.threshold_ns, 8 * jitter);
  const auto beyond = std::count_if(jumps.begin(), jumps.end(), [&](std::int64_t j) { return j > threshold; });
  if (static_cast<std::size_t>(beyond) * 20 > jumps.size() && beyond > 2) return steps;
  const std::size_t w = std::max<std::size_t>(options.window, 1);

  std::size_t segment = 0;  // first line of the current run of increasing monotonic stamps
  std::size_t last_step = 0;
  for (std::size_t i = 1; i < n; ++i) {
    if (mono[i] < mono[i - 1]) {
      segment = last_step = i;
      continue;
    }
    const std::int64_t allowance = threshold + slew(options.slew_ppm, mono[i] - mono[i - 1]);
    if (std::llabs(d[i] - d[i - 1]) <= allowance) continue;
    // The windows: up to w lines each side, within this segment and not across the last step.
    const std::size_t lo = std::max({segment, last_step, i >= w ? i - w : std::size_t{0}});
    std::size_t hi = i;
    while (hi < n && hi - i < w && (hi == i || mono[hi] >= mono[hi - 1])) ++hi;
    const std::vector<std::int64_t> before(d.begin() + static_cast<std::ptrdiff_t>(lo),
                                           d.begin() + static_cast<std::ptrdiff_t>(i));
    const std::vector<std::int64_t> after(d.begin() + static_cast<std::ptrdiff_t>(i),
                                          d.begin() + static_cast<std::ptrdiff_t>(hi));
    const std::int64_t size = median_of(after) - median_of(before);
    const std::int64_t span = mono[hi - 1] - mono[lo];
    if (std::llabs(size) <= threshold + slew(options.slew_ppm, span)) continue;  // one late printk
    const auto [bmin, bmax] = std::minmax_element(before.begin(), before.end());
    const auto [amin, amax] = std::minmax_element(after.begin(), after.end());
    store::ClockStep step;
    step.at_ns = realtime_ns[i];
    step.earliest_ns = realtime_ns[i];  // the lines' order places it: between line i-1 and line i
    step.size_ns = size;
    step.size_max_ns = (*bmax - *bmin) + (*amax - *amin) + slew(options.slew_ppm, span);
    step.size_est_ns = (3 * jitter + 1) / 2;
    step.origin = "kernel_log";
    steps.push_back(step);
    last_step = i;
  }
  return steps;
}

}  // namespace m2mlat::analysis
