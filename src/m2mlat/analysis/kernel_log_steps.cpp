// Clock steps from a kernel log's realtime and printk stamps (rules in kernel_log_steps.hpp).
#include "m2mlat/analysis/kernel_log_steps.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <limits>

#include "m2mlat/analysis/kernel_log_fine_steps.hpp"
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
  out.limits.fast_slew_places = places;
  out.limits.hidden_below_ns = hidden;
}

}  // namespace

std::string fast_slewing_note(std::size_t places, std::int64_t hidden_below_ns, double slew_ppm) {
  return fmt::format(
      "the kernel log's realtime clock slews faster than {:g} ppm at {} places: steps cannot be told from "
      "slewing (none corrected up to {:.1f} ms; the pairs keep their stamps); chrony's maxslewrate {:g} "
      "makes them visible",
      slew_ppm, places, static_cast<double>(hidden_below_ns) / 1e6, slew_ppm);
}

std::vector<std::string> log_clock_notes(const LogClockLimits& limits) {
  std::vector<std::string> out;
  if (limits.fast_slew_places != 0) out.push_back(fast_slewing_note(limits.fast_slew_places, limits.hidden_below_ns));
  else if (limits.any())
    out.push_back(fmt::format("the kernel log's realtime clock wanders between its lines: steps below {:.1f} ms may go "
                              "unseen (from that size on 95 % are found; closer lines or a steadier clock show smaller ones)",
                              static_cast<double>(limits.wander_floor_ns) / 1e6));
  return out;
}

std::vector<store::ClockStep> kernel_log_steps(std::span<const std::int64_t> realtime_ns,
                                               std::span<const std::int64_t> log_time_us,
                                               const KernelLogStepOptions& options) {
  return kernel_log_clock(realtime_ns, log_time_us, options).steps;
}

namespace {

constexpr std::int64_t kClockSetNs = 946'684'800'000'000'000;  // 2000-01-01: stamps before it are a clock never set

// A level of one segment: the lines [first, last] but those left out (kept as ranges, so that a log
// of 10^7 lines costs no column of line numbers).
struct Level {
  std::size_t first = 0, last = 0;
};

}  // namespace

KernelLogClock kernel_log_clock(std::span<const std::int64_t> realtime_ns, std::span<const std::int64_t> log_time_us,
                                const KernelLogStepOptions& options) {
  KernelLogClock out;
  auto& steps = out.steps;
  std::vector<std::int64_t> step_mono;  // per step: its new level's first line's monotonic stamp, ns
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
  const auto agree = [&](std::size_t a, std::size_t b) {
    return std::llabs(d_at(b) - d_at(a)) <= threshold + log_slew(options.slew_ppm, mono(b) - mono(a));
  };
  std::size_t beyond = 0;
  for (const std::size_t line : lines) beyond += !agree(line - 1, line);
  if (beyond * 4 > jumps.size() && beyond > 2) return out;
  const std::size_t w = std::max<std::size_t>(options.window, 1);
  const std::size_t confirm = std::max<std::size_t>(options.confirm, 2);

  // Steps inside a level (kernel_log_fine_steps.hpp), each with the index in steps it goes before.
  std::vector<std::pair<std::size_t, store::ClockStep>> fine;
  FineStepOptions fine_options;
  std::size_t floor_lines = 0;  // the kept lines of the level wander_floor_ns is of
  fine_options.min_size_ns = options.threshold_ns / 2;
  fine_options.slew_ppm = options.slew_ppm;
  std::vector<bool> out_lines(n, false);  // the lines left out so far: skipped inside a level's range (n bits)
  const auto leave_out = [&](std::size_t line, LineFault why) {
    out.left_out.emplace_back(line, why);
    out_lines[line] = true;
  };
  // Up to w kept lines of a level from its end (back) or its start, d of each.
  const auto window = [&](const Level& l, bool from_end, std::size_t& far_line) {
    std::vector<std::int64_t> d;
    for (std::size_t k = 0; k <= l.last - l.first && d.size() < w; ++k) {
      const std::size_t i = from_end ? l.last - k : l.first + k;
      if (out_lines[i]) continue;
      d.push_back(d_at(i));
      far_line = i;
    }
    return d;
  };

  for (std::size_t segment = 0; segment < n;) {
    std::size_t end = segment + 1;  // one past the segment's last line
    while (end < n && mono(end) >= mono(end - 1)) ++end;
    const bool from_boot = mono(segment) <= options.first_sync_within_ns;
    // Lines of short runs before the first confirmed run: no level says which clock stamped them.
    const auto unplaced = [&](std::size_t line) {
      leave_out(line, from_boot && mono(line) <= options.first_sync_within_ns ? LineFault::before_sync
                                                                              : LineFault::outlier);
    };
    std::vector<Level> levels;
    std::vector<std::pair<std::size_t, std::size_t>> moving;  // per step between levels k and k + 1: [first, last), may be empty
    std::vector<std::size_t> pending;  // lines of short runs since the last level
    // Runs: lines whose d agrees with the line before; each run, once complete, is placed.
    const auto place = [&](std::size_t first, std::size_t past) {
      if (past - first < confirm) {
        for (std::size_t i = first; i < past; ++i) pending.push_back(i);
        return;
      }
      Level next{first, past - 1};
      if (levels.empty()) {
        // Before the first level: lines that agree with it are of it, the others unplaced.
        for (const std::size_t i : pending) {
          if (agree(i, first))
            next.first = std::min(next.first, i);
          else
            unplaced(i);
        }
        // A line that agrees before one that does not: the later one is an outlier inside the level.
      } else {
        auto& before = levels.back();
        const std::size_t last = before.last;
        if (agree(last, first)) {
          // The same level on both sides: of the lines between, those that disagree are outliers.
          for (const std::size_t i : pending)
            if (!agree(last, i)) leave_out(i, LineFault::outlier);
          before.last = past - 1;
          pending.clear();
          return;
        }
        // A step: of the lines between, those that agree with one level are of it, those between the
        // two levels were stamped while the clock moved (in that order), the others are outliers.
        const std::int64_t lo = std::min(d_at(last), d_at(first)) - threshold;
        const std::int64_t hi = std::max(d_at(last), d_at(first)) + threshold;
        std::pair<std::size_t, std::size_t> moved{0, 0};
        bool in_next = false;
        for (const std::size_t i : pending) {
          if (agree(i, first)) {
            if (!in_next) next.first = i;
            in_next = true;
          } else if (!in_next && moved.second == 0 && agree(last, i)) {
            before.last = i;
          } else if (!in_next && d_at(i) >= lo && d_at(i) <= hi) {
            if (moved.second == 0) moved.first = i;
            moved.second = i + 1;
          } else {
            leave_out(i, LineFault::outlier);
          }
        }
        // Lines in the ranges that the classes above did not take are outliers already.
        moving.push_back(moved);
      }
      levels.push_back(next);
      pending.clear();
    };
    std::size_t run_first = segment;
    for (std::size_t i = segment + 1; i <= end; ++i)
      if (i == end || !agree(i - 1, i)) {
        place(run_first, i);
        run_first = i;
      }
    // Short runs after the last level: no later line confirms them. (A segment without a confirmed
    // level says nothing of its lines.)
    if (!levels.empty()) {
      for (const std::size_t i : pending) {
        if (agree(levels.back().last, i))
          levels.back().last = i;
        else
          leave_out(i, LineFault::outlier);
      }
    }
    const auto leave_out_level = [&](const Level& l, LineFault why) {
      for (std::size_t i = l.first; i <= l.last; ++i)
        if (!out_lines[i]) leave_out(i, why);
    };

    // The first synchronisation: the segment's first level before its first step is a clock not yet
    // set when the segment starts at boot and that level ends within first_sync_within_ns of it, or
    // when its stamps lie before 2000 (a board without a real-time clock counts from 1970).
    std::size_t first_level = 0;
    if (levels.size() == 1 && realtime_ns[levels.front().last] < kClockSetNs)
      leave_out_level(levels.front(), LineFault::before_sync);
    if (levels.size() > 1) {
      const auto& l0 = levels.front();
      if ((from_boot && mono(l0.last) <= options.first_sync_within_ns) || realtime_ns[l0.last] < kClockSetNs) {
        leave_out_level(l0, LineFault::before_sync);
        if (moving.front().second != 0)
          leave_out_level({moving.front().first, moving.front().second - 1}, LineFault::before_sync);
        first_level = 1;
      }
    }
    const auto within = [&](const Level& l) {
      std::vector<std::size_t> kept;
      std::vector<std::int64_t> m, d;
      for (std::size_t i = l.first; i <= l.last; ++i)
        if (!out_lines[i]) kept.push_back(i), m.push_back(mono(i)), d.push_back(d_at(i));
      const auto found = fine_steps(m, d, fine_options);
      if (kept.size() > floor_lines && found.floor_ns != 0) floor_lines = kept.size(), out.limits.wander_floor_ns = found.floor_ns;
      for (const auto& f : found.steps) {
        store::ClockStep step;
        step.earliest_ns = step.at_ns = realtime_ns[kept[f.line]];
        step.size_ns = f.size_ns;
        step.size_est_ns = f.sd_ns;
        step.size_max_ns = 4 * f.sd_ns;
        step.origin = "kernel_log";
        fine.emplace_back(steps.size(), step);
      }
    };
    for (std::size_t k = first_level; k < levels.size(); ++k) {
      within(levels[k]);
      if (k + 1 == levels.size()) break;
      const auto& moved = moving[k];
      std::size_t window_first = 0, window_last = 0;
      const auto before = window(levels[k], true, window_first);
      const auto after = window(levels[k + 1], false, window_last);
      const std::int64_t size = log_median(after) - log_median(before);
      const auto [bmin, bmax] = std::minmax_element(before.begin(), before.end());
      const auto [amin, amax] = std::minmax_element(after.begin(), after.end());
      store::ClockStep step;
      const std::size_t first_after = moved.second == 0 ? levels[k + 1].first : moved.first;
      step.earliest_ns = realtime_ns[first_after];  // the lines' order places it: after the old level's last line
      step.size_ns = size;
      step.size_max_ns = (*bmax - *bmin) + (*amax - *amin) + log_slew(options.slew_ppm, mono(window_last) - mono(window_first));
      step.size_est_ns = (3 * jitter + 1) / 2;
      if (moved.second == 0) {
        step.at_ns = realtime_ns[levels[k + 1].first];
      } else {
        // The clock moved over several lines (a daemon slewing faster than the kernel's 500 ppm): the
        // lines between are neither here nor there; at_ns = the new level's first stamp + size puts
        // them in the overlap correct_side flags. Its size is then known only to the slewing's extent:
        // as uniform within that bound.
        step.at_ns = realtime_ns[levels[k + 1].first] + size;
        step.size_est_ns = std::max(step.size_est_ns, static_cast<std::int64_t>(std::ceil(
                                                          static_cast<double>(step.size_max_ns) / std::sqrt(3.0))));
      }
      step.origin = "kernel_log";
      steps.push_back(step);
      step_mono.push_back(mono(levels[k + 1].first));
    }
    segment = end;
  }
  std::sort(out.left_out.begin(), out.left_out.end());
  drop_fast_slewing(out, step_mono, options);
  // A clock slewing beyond the bound hides its small steps too.
  if (out.limits.fast_slew_places == 0 && !fine.empty()) {
    std::vector<store::ClockStep> merged;
    merged.reserve(steps.size() + fine.size());
    std::size_t next = 0;
    for (std::size_t k = 0; k <= steps.size(); ++k) {
      for (; next < fine.size() && fine[next].first == k; ++next) merged.push_back(fine[next].second);
      if (k < steps.size()) merged.push_back(steps[k]);
    }
    steps = std::move(merged);
  }
  return out;
}

std::vector<store::UnknownClock> unknown_clock_runs(std::span<const std::int64_t> realtime_ns,
                                                    std::span<const std::pair<std::size_t, LineFault>> left_out) {
  std::vector<store::UnknownClock> out;
  if (left_out.empty()) return out;
  // The kept lines' stamps, sorted: a range of left-out stamps may not hold one (else line by line).
  std::vector<std::int64_t> kept;
  kept.reserve(realtime_ns.size() - left_out.size());
  for (std::size_t i = 0, k = 0; i < realtime_ns.size(); ++i) {
    if (k < left_out.size() && left_out[k].first == i) {
      ++k;
      continue;
    }
    kept.push_back(realtime_ns[i]);
  }
  std::sort(kept.begin(), kept.end());
  const auto holds_kept = [&](std::int64_t from, std::int64_t to) {
    const auto it = std::lower_bound(kept.begin(), kept.end(), from);
    return it != kept.end() && *it <= to;
  };
  const auto reason = [](LineFault f) { return f == LineFault::outlier ? "outlier" : "before_sync"; };
  for (std::size_t k = 0; k < left_out.size();) {
    // A run of consecutive lines of one reason.
    std::size_t e = k + 1;
    while (e < left_out.size() && left_out[e].first == left_out[e - 1].first + 1 && left_out[e].second == left_out[k].second) ++e;
    std::int64_t from = realtime_ns[left_out[k].first], to = from;
    for (std::size_t j = k; j < e; ++j) from = std::min(from, realtime_ns[left_out[j].first]), to = std::max(to, realtime_ns[left_out[j].first]);
    if (!holds_kept(from, to)) {
      out.push_back({from, to, static_cast<std::int64_t>(e - k), reason(left_out[k].second)});
    } else {
      for (std::size_t j = k; j < e; ++j) {
        const std::int64_t t = realtime_ns[left_out[j].first];
        if (!holds_kept(t, t)) out.push_back({t, t, 1, reason(left_out[j].second)});  // a stamp also kept stays
      }
    }
    k = e;
  }
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
