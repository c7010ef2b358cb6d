// Clock steps from a kernel log's realtime and printk stamps (rules in kernel_log_steps.hpp).
#include "m2mlat/analysis/kernel_log_steps.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <limits>

#include "m2mlat/core/saturating.hpp"

namespace m2mlat::analysis {

namespace {

std::int64_t log_median(std::vector<std::int64_t> v) {
  const auto mid = v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2);
  std::nth_element(v.begin(), mid, v.end());
  if (v.size() % 2 == 1) return *mid;
  const auto low = *std::max_element(v.begin(), mid);
  return low + (*mid - low) / 2;
}

std::int64_t log_slew(double ppm, std::int64_t span_ns) {
  return static_cast<std::int64_t>(std::ceil(ppm * 1e-6 * static_cast<double>(std::llabs(span_ns))));
}

// The printk jitter of a log whose clock may be slewing for most of it (a follower taking over a
// large step slews at 500 ppm for minutes: every |d[i] - d[i-1]| then holds the slew too): the median
// distance of d[i] from the line between its two neighbours (time-weighted), over at most 2^16 lines.
std::int64_t slew_free_jitter(std::span<const std::int64_t> realtime_ns, std::span<const std::int64_t> log_time_us,
                              std::size_t n) {
  std::vector<std::int64_t> off;
  const std::size_t stride = std::max<std::size_t>(1, (n - 1) >> 16);
  const auto d_at = [&](std::size_t i) { return realtime_ns[i] - log_time_us[i] * 1000; };
  for (std::size_t i = 1; i + 1 < n; i += stride) {
    const std::int64_t span = log_time_us[i + 1] - log_time_us[i - 1];
    if (log_time_us[i] < log_time_us[i - 1] || log_time_us[i + 1] < log_time_us[i] || span <= 0) continue;
    const double f = static_cast<double>(log_time_us[i] - log_time_us[i - 1]) / static_cast<double>(span);
    const double line = static_cast<double>(d_at(i - 1)) + f * static_cast<double>(d_at(i + 1) - d_at(i - 1));
    off.push_back(std::llround(std::fabs(static_cast<double>(d_at(i)) - line)));
  }
  return off.empty() ? 0 : log_median(std::move(off));
}

// The slewing among `steps` (rules in kernel_log_steps.hpp); step_mono: each step's last line's
// monotonic stamp, ns.
void drop_fast_slewing(KernelLogClock& out, std::span<const std::int64_t> step_mono,
                       const KernelLogStepOptions& options) {
  auto& steps = out.steps;
  std::vector<bool> slewing(steps.size(), false);
  for (std::size_t k = 0; k < steps.size(); ++k) {
    const std::int64_t first = *steps[k].size_ns;
    std::int64_t sum = first;
    for (std::size_t j = k + 1; j < steps.size() && step_mono[j] >= step_mono[k] &&
                                step_mono[j] - step_mono[k] <= options.undone_within_ns;
         ++j) {
      sum += *steps[j].size_ns;
      if ((*steps[j].size_ns > 0) != (first > 0) && 2 * std::llabs(sum) <= std::llabs(first)) {
        for (std::size_t m = k; m <= j; ++m) slewing[m] = true;
        break;
      }
    }
  }
  std::size_t places = 0;
  std::int64_t largest = 0;
  for (std::size_t k = 0; k < steps.size(); ++k)
    if (slewing[k]) {
      ++places;
      largest = std::max<std::int64_t>(largest, std::llabs(*steps[k].size_ns));
    }
  if (places < std::max<std::size_t>(options.fast_places_min, 2)) return;
  // The bound does not hold: only steps that stand out of the slewing remain.
  const std::int64_t hidden = 2 * largest;
  std::vector<store::ClockStep> kept;
  for (std::size_t k = 0; k < steps.size(); ++k) {
    if (!slewing[k] && std::llabs(*steps[k].size_ns) > hidden)
      kept.push_back(steps[k]);
    else if (!slewing[k])
      ++places;
  }
  steps = std::move(kept);
  out.fast_slew_places = places;
  out.hidden_below_ns = hidden;
}

}  // namespace

std::string fast_slewing_note(std::size_t places, std::int64_t hidden_below_ns, double slew_ppm) {
  return fmt::format(
      "the kernel log's realtime clock slews faster than {:g} ppm at {} places: steps cannot be told from "
      "slewing (none corrected up to {:.1f} ms; the pairs keep their stamps); chrony's maxslewrate {:g} "
      "makes them visible",
      slew_ppm, places, static_cast<double>(hidden_below_ns) / 1e6, slew_ppm);
}

std::vector<store::ClockStep> kernel_log_steps(std::span<const std::int64_t> realtime_ns,
                                               std::span<const std::int64_t> log_time_us,
                                               const KernelLogStepOptions& options) {
  return kernel_log_clock(realtime_ns, log_time_us, options).steps;
}

KernelLogClock kernel_log_clock(std::span<const std::int64_t> realtime_ns, std::span<const std::int64_t> log_time_us,
                                const KernelLogStepOptions& options) {
  KernelLogClock out;
  auto& steps = out.steps;
  std::vector<std::int64_t> step_mono;  // per step: its last jump's line's monotonic stamp, ns
  const std::size_t n = std::min(realtime_ns.size(), log_time_us.size());
  if (n < 2) return out;
  // Computed per line, not stored: a log of 10^7 lines costs no further columns.
  const auto mono = [&](std::size_t i) { return log_time_us[i] * 1000; };
  const auto d_at = [&](std::size_t i) { return realtime_ns[i] - mono(i); };
  // The jitter from at most 2^16 line pairs spread over the log (a median needs no more).
  const std::size_t stride = std::max<std::size_t>(1, (n - 1) >> 16);
  std::vector<std::int64_t> jumps;
  std::vector<std::size_t> lines;  // the later line of each jump
  for (std::size_t i = 1; i < n; i += stride)
    if (mono(i) >= mono(i - 1)) {
      jumps.push_back(std::llabs(d_at(i) - d_at(i - 1)));
      lines.push_back(i);
    }
  if (jumps.empty()) return out;
  const std::int64_t jitter = log_median(jumps);
  // Stamps that do not follow the realtime ones (written by a script, lines of another clock) are no
  // clock to compare with: a typical jump beyond the smallest step, or jumps beyond what slewing
  // allows at more than one line pair in 4, and nothing is said.
  if (jitter > options.threshold_ns) return out;
  const std::int64_t threshold = std::max(options.threshold_ns, 8 * jitter);
  std::size_t beyond = 0;
  for (std::size_t k = 0; k < jumps.size(); ++k)
    if (jumps[k] > threshold + log_slew(options.slew_ppm, mono(lines[k]) - mono(lines[k] - 1))) ++beyond;
  if (beyond * 4 > jumps.size() && beyond > 2) return out;
  const std::size_t w = std::max<std::size_t>(options.window, 1);

  std::size_t segment = 0;  // first line of the current run of increasing monotonic stamps
  std::size_t last_step = 0;
  struct Open {  // the last step, while a next jump may continue it
    bool active = false;
    std::size_t line = 0;
    std::int64_t size = 0, before_median = 0, before_range = 0, lo_mono = 0;
  };
  Open open;
  for (std::size_t i = 1; i < n; ++i) {
    if (mono(i) < mono(i - 1)) {
      segment = last_step = i;
      open.active = false;
      continue;
    }
    const std::int64_t allowance = threshold + log_slew(options.slew_ppm, mono(i) - mono(i - 1));
    if (std::llabs(d_at(i) - d_at(i - 1)) <= allowance) continue;
    // The windows: up to w lines each side, within this segment and not across the last step.
    const std::size_t lo = std::max({segment, last_step, i >= w ? i - w : std::size_t{0}});
    std::size_t hi = i;
    while (hi < n && hi - i < w && (hi == i || mono(hi) >= mono(hi - 1))) ++hi;
    // Kept by the lines on both sides: most lines after the jump lie on the far side of the midpoint
    // between the two lines, and most lines before it on the near side. One late printk (one low d)
    // is kept by one side only. The jump itself already exceeds what slewing can do between its two
    // lines, so this only tells a level that stays from one that comes back. (The rule before: the
    // windows' medians had to differ by more than the slewing over both windows, 500 ppm over ~8
    // gaps: where the lines are seconds apart that hid steps of up to ~10 ms.)
    const std::int64_t way = d_at(i) > d_at(i - 1) ? 1 : -1;
    const std::int64_t mid2 = d_at(i - 1) + d_at(i);  // twice the midpoint, ns
    std::size_t after_kept = 0, before_kept = 0;
    for (std::size_t k = i; k < hi; ++k) after_kept += way * (2 * d_at(k) - mid2) > 0;
    for (std::size_t k = lo; k < i; ++k) before_kept += way * (mid2 - 2 * d_at(k)) > 0;
    if (2 * after_kept <= hi - i || 2 * before_kept <= i - lo) continue;  // one late printk
    std::vector<std::int64_t> before, after;
    for (std::size_t k = lo; k < i; ++k) before.push_back(d_at(k));
    for (std::size_t k = i; k < hi; ++k) after.push_back(d_at(k));
    const std::int64_t size = log_median(after) - log_median(before);
    const std::int64_t span = mono(hi - 1) - mono(lo);
    const auto [bmin, bmax] = std::minmax_element(before.begin(), before.end());
    const auto [amin, amax] = std::minmax_element(after.begin(), after.end());
    // A jump within `window` lines of the last step, the same way, continues it: a clock slewed
    // faster than the kernel's 500 ppm (a daemon catching up with a stepped reference) moves over a
    // few lines. One step from before the first jump to after the last; the lines between are
    // neither here nor there (stamped while it moved): at_ns = the last jump's stamp + size puts
    // them in the overlap correct_side flags.
    if (open.active && i - open.line <= w && (size > 0) == (open.size > 0)) {
      auto& merged = steps.back();
      const std::int64_t total = log_median(after) - open.before_median;
      const std::int64_t total_span = mono(hi - 1) - open.lo_mono;
      merged.size_ns = total;
      merged.at_ns = realtime_ns[i] + total;
      merged.size_max_ns = open.before_range + (*amax - *amin) + log_slew(options.slew_ppm, total_span);
      // Its size is then known only to the slewing's extent: as uniform within that bound.
      merged.size_est_ns = std::max(merged.size_est_ns,
                                    static_cast<std::int64_t>(std::ceil(static_cast<double>(merged.size_max_ns) / std::sqrt(3.0))));
      step_mono.back() = mono(i);
      open.line = i;
      open.size = total;
      last_step = i;
      continue;
    }
    store::ClockStep step;
    step.at_ns = realtime_ns[i];
    step.earliest_ns = realtime_ns[i];  // the lines' order places it: between line i-1 and line i
    step.size_ns = size;
    step.size_max_ns = (*bmax - *bmin) + (*amax - *amin) + log_slew(options.slew_ppm, span);
    step.size_est_ns = (3 * jitter + 1) / 2;
    step.origin = "kernel_log";
    steps.push_back(step);
    step_mono.push_back(mono(i));
    open = Open{true, i, size, log_median(before), *bmax - *bmin, mono(lo)};
    last_step = i;
  }
  drop_fast_slewing(out, step_mono, options);
  return out;
}

LogStamps log_stamps(std::span<const formats::KernelLogRecord> records) {
  LogStamps out;
  for (const auto& k : records) {
    if (!k.log_time_us) return {};
    out.realtime_ns.push_back(k.time_ns);
    out.log_time_us.push_back(*k.log_time_us);
  }
  return out;
}

std::vector<store::ClockStep> kernel_log_followed(std::span<const store::ClockStep> other_steps,
                                                  std::span<const store::ClockStep> own_steps,
                                                  std::span<const std::int64_t> realtime_ns,
                                                  std::span<const std::int64_t> log_time_us,
                                                  const KernelLogStepOptions& options) {
  std::vector<store::ClockStep> out;
  const std::size_t n = std::min(realtime_ns.size(), log_time_us.size());
  if (n < 2 || other_steps.empty()) return out;
  const auto mono = [&](std::size_t i) { return log_time_us[i] * 1000; };
  const auto d_at = [&](std::size_t i) { return realtime_ns[i] - mono(i); };
  // Not kernel_log_clock's J: a follower slewing a large step away for most of its log would read as
  // stamps that follow no clock (its median jump is the slew's ~1 ms a line).
  const std::int64_t jitter = slew_free_jitter(realtime_ns, log_time_us, n);
  if (jitter > options.threshold_ns) return out;  // no clock to compare with
  const std::int64_t threshold = std::max(options.threshold_ns, 8 * jitter);
  const std::size_t w = 2 * std::max<std::size_t>(options.window, 1);
  for (const auto& step : other_steps) {
    if (!step.size_ns || std::llabs(*step.size_ns) <= threshold) continue;
    const std::int64_t size = *step.size_ns;
    const std::int64_t magnitude = std::llabs(size);
    const std::int64_t way = size > 0 ? 1 : -1;
    // The first line stamped at or after the step (the log is in time order but where this board
    // stepped itself: a binary search may land a line off there, which only shifts the window).
    const auto first = static_cast<std::size_t>(
        std::lower_bound(realtime_ns.begin(), realtime_ns.begin() + static_cast<std::ptrdiff_t>(n), step.earliest_ns) -
        realtime_ns.begin());
    if (first < 2 || first >= n) continue;
    std::vector<std::int64_t> before;
    for (std::size_t k = first >= w ? first - w : 0; k < first; ++k)
      if (k == 0 || mono(k) >= mono(k - 1)) before.push_back(d_at(k));
    if (before.empty()) continue;  // a reboot just before: no level to follow from
    const std::int64_t d0 = log_median(before);
    // Followed: d moved its way, by slewing only, beyond half the step or beyond the threshold plus
    // half the slewing bound over the time since (a daemon slewing the step away runs at the bound; a
    // crystal's drift, tens of ppm, never gets there), at two lines in a row (not one late printk).
    const std::int64_t horizon_ns = 64'000'000'000 + 2 * static_cast<std::int64_t>(std::ceil(
                                                              static_cast<double>(magnitude) * 1e6 / options.slew_ppm));
    const auto beyond = [&](std::size_t k) {
      const std::int64_t needed = std::min(magnitude / 2, threshold + log_slew(options.slew_ppm / 2, mono(k) - mono(first)));
      return way * (d_at(k) - d0) > needed;
    };
    // This board's own step in that time: its own correction says what it did (a step, not a slew).
    const bool stepped_too = std::any_of(own_steps.begin(), own_steps.end(), [&](const store::ClockStep& own) {
      return own.at_ns >= realtime_ns[first - 1] && own.earliest_ns <= realtime_ns[first] + horizon_ns;
    });
    if (stepped_too) continue;
    std::size_t moved = n;
    for (std::size_t k = first; k < n && mono(k) - mono(first) <= horizon_ns; ++k) {
      if (mono(k) < mono(k - 1)) break;  // a reboot
      if (k > first && beyond(k) && beyond(k - 1)) {
        moved = k;
        break;
      }
    }
    if (moved == n) continue;
    store::ClockStep follow;
    follow.origin = "followed";
    follow.size_ns = size;
    follow.earliest_ns = step.earliest_ns;
    // Back in step: two lines in a row (or the last) within `close` of the old level plus the step.
    const std::int64_t close = std::max({magnitude / 16, 4 * jitter, options.threshold_ns});
    const auto left = [&](std::size_t k) { return k == n ? 0 : std::llabs(d_at(k) - d0 - size); };
    std::size_t back = moved;
    while (back < n && !(left(back) <= close && left(back + 1) <= close)) ++back;
    if (back == n) {
      follow.at_ns = std::numeric_limits<std::int64_t>::max() / 2;  // never back in step: flagged to the end
    } else {
      // As followed_steps: stamps in [earliest, at - size) are mid-slew (flagged), the rest corrected.
      follow.at_ns = realtime_ns[back] + size;
      const std::int64_t rest = std::max(left(back), left(back + 1));
      follow.size_max_ns = core::saturating_add(step.size_max_ns, 2 * rest);
      const auto est = static_cast<double>(step.size_est_ns == store::kUnknownSize ? 0 : step.size_est_ns);
      follow.size_est_ns = std::llround(std::sqrt(est * est + static_cast<double>(rest) * static_cast<double>(rest)));
    }
    out.push_back(follow);
  }
  return out;
}

}  // namespace m2mlat::analysis
