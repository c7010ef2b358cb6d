// Clock steps seen in a kernel log. Each GPIO line carries two stamps of the same moment: the
// module's CLOCK_REALTIME nanoseconds of the edge, and the log's own printk stamp ("[ s.us]" or the
// kmsg header's us since boot), which is CLOCK_MONOTONIC and never stepped. Per line,
//   d = realtime - monotonic = (the realtime clock's offset from boot) - (the printk delay)
// is constant up to the printk delay (us .. ms, always >= 0) and the kernel's slewing of
// CLOCK_REALTIME (<= 500 ppm: MAXFREQ plus the PLL's phase slew). A change of d between two
// consecutive lines beyond that, which the next lines keep (a single late printk is no step), is a
// step of CLOCK_REALTIME between the two lines.
//
// The model: d is a level that holds (up to the jitter and the slewing) until a step moves it, plus
// lines that belong to no level. The jitter J is measured from the lines themselves: the median of
// |d[i] - d[i-1]| over the log. Two lines agree when their d differ by at most
// max(threshold, 8 J) + slew_ppm * (time between them). Lines that agree with the line before form a
// run; a run of at least `confirm` lines is a level. Between two levels:
//   - when they agree, the lines between are outliers (a line of another clock, a late printk): their
//     events are left out (reason "outlier", LineFault), and they never move another event;
//   - else the clock stepped between them: the lines between that lie between both levels were
//     stamped while it moved (a daemon slewing faster than 500 ppm catches up over a few lines), the
//     others are outliers.
// Short runs before a segment's first level or after its last are confirmed by no level on one side:
// left out ("before_sync" when stamped within first_sync_within_ns of boot, else "outlier").
// A log that begins before the board's first synchronisation: when a segment starts at boot and its
// first level ends within first_sync_within_ns of uptime (chronyd's makestep acts in its first
// updates after boot), or that level's stamps lie before 2000 (a board without a real-time clock
// counts from 1970), that first level is a clock not yet set: its lines are left out ("before_sync")
// and the step is none (the later stamps are on the set clock, and nothing is shifted by it).
// A step's size is the difference of the medians of up to `window` lines of each level beside it; the
// size's bound is the spread (max - min of d) of both windows plus slew_ppm over the time between the
// windows' first and last lines, its standard uncertainty 1.5 J (one line's d has a standard
// deviation of about J / 0.95 for a normal jitter; a difference of two is sqrt(2) that). The step lies
// between the old level's last line and the next line: that next line is the first stamp surely after
// it. A step over lines stamped while the clock moved: at_ns = the new level's first stamp + size (the
// lines between are flagged, see clock_steps.hpp), its standard uncertainty its bound / sqrt(3).
// Stamps that are no clock beside the realtime ones (J above the threshold, or jumps beyond what
// slewing allows at more than one line pair in 4: a script's "[ 1.000000]" counter) give no steps.
// A clock that breaks the slewing bound is no clock to find steps of its size with either: a daemon
// that slews faster than slew_ppm (chrony's default maxslewrate is 83333 ppm) moves d by ms and back
// within seconds. A "step" that the next ones undo within `undone_within_ns` (their running sum back
// to at most half of it, the last of them the other way) is such slewing; when the log shows
// `fast_places_min` of them, the clock breaks the bound: none of them is a step, and of the others
// only those larger than twice the largest slewing excursion are (a genuine step stands out of the
// slewing; smaller ones cannot be told from it and are counted as slewing places too). The pairs keep
// their stamps uncorrected and unflagged (no step of unknown size: that would drop every later pair);
// the caller reports the places and the size below which a step may hide.
// Inside each level (its kept lines), steps too small for the agreement test are sought by a model of
// d (kernel_log_fine_steps.hpp); they go with the others. A clock that breaks the bound keeps none.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include "m2mlat/formats/imported.hpp"
#include "m2mlat/store/clock_step.hpp"

namespace m2mlat::analysis {

struct KernelLogStepOptions {
  std::int64_t threshold_ns = 1'000'000;  // the smallest step reported, ns
  double slew_ppm = 500;                  // the fastest slewing that is no step, ppm
  std::size_t window = 4;                 // lines on each side that confirm a step and measure it
  std::int64_t undone_within_ns = 60'000'000'000;  // a "step" undone within this is slewing, ns (monotonic)
  std::size_t fast_places_min = 4;                 // slewing "steps" that show the bound broken
  std::size_t confirm = 3;                         // lines in a row that make a level (at least 2)
  std::int64_t first_sync_within_ns = 600'000'000'000;  // a first level ending this soon after boot precedes the first sync, ns
};

// Why a line's event is left out (kernel_log_steps.hpp's model).
enum class LineFault : std::uint8_t { outlier, before_sync };

// A kernel log's two stamps per GPIO line, in file order.
struct LogStamps {
  std::vector<std::int64_t> realtime_ns, log_time_us;
};
// The stamps of an imported kernel log's lines; empty without lines, or when a line lacks the log's
// own stamp (then nothing to compare the realtime stamps with).
LogStamps log_stamps(std::span<const formats::KernelLogRecord> records);

// The steps a kernel log cannot show: hidden in a clock slewing beyond the bound, or in its wander.
struct LogClockLimits {
  std::size_t fast_slew_places = 0;  // places d moved faster than slew_ppm: not steps (0: bound held)
  std::int64_t hidden_below_ns = 0;  // steps up to this size cannot be told from that slewing, ns
  // Inside its longest level, steps from this size on are found 95 % of the time (kernel_log_fine_steps.hpp), ns.
  std::int64_t wander_floor_ns = 0;
  // Something to say: the bound broken, or a floor above the smallest step reported (threshold_ns).
  bool any(std::int64_t threshold_ns = KernelLogStepOptions{}.threshold_ns) const {
    return fast_slew_places != 0 || wander_floor_ns > threshold_ns;
  }
};

// What a kernel log's stamps say about its realtime clock.
struct KernelLogClock {
  std::vector<store::ClockStep> steps;
  LogClockLimits limits;
  std::vector<std::pair<std::size_t, LineFault>> left_out;  // lines (index, reason) whose clock is unknown, in order
};

// realtime_ns and log_time_us: one entry per line, in file order (same length). Lines whose
// monotonic stamp goes back (a reboot, two logs joined) start afresh: no step is seen across them.
KernelLogClock kernel_log_clock(std::span<const std::int64_t> realtime_ns, std::span<const std::int64_t> log_time_us,
                                const KernelLogStepOptions& options = {});
// A clock's left-out lines as the store's records: runs of consecutive lines of one reason as one
// range of stamps when no kept line's stamp lies in it, else line by line (a left-out line whose very
// stamp a kept line has too stays in: its event cannot be told from the kept one).
std::vector<store::UnknownClock> unknown_clock_runs(std::span<const std::int64_t> realtime_ns,
                                                    std::span<const std::pair<std::size_t, LineFault>> left_out);
// The note stats, report and import give for a clock that broke the bound: "the kernel log's realtime
// clock slews faster than 500 ppm at K places: ...".
std::string fast_slewing_note(std::size_t places, std::int64_t hidden_below_ns, double slew_ppm = 500);
// The notes of LogClockLimits::any(): the fast slewing's, and "the kernel log's realtime clock wanders
// between its lines: steps below X ms may go unseen ...".
std::vector<std::string> log_clock_notes(const LogClockLimits& limits);
// kernel_log_clock's steps alone.
std::vector<store::ClockStep> kernel_log_steps(std::span<const std::int64_t> realtime_ns,
                                               std::span<const std::int64_t> log_time_us,
                                               const KernelLogStepOptions& options = {});

// The other board's steps this board took over, seen in this board's kernel log (the kernel-log
// counterpart of clock_steps.hpp's followed_steps, which reads a daemon's offsets). In a co-referenced
// rig the vehicle's daemon follows the operator's clock: after the operator's step of size S it
// slews onto the new timescale, which this log shows as d = realtime - printk moving by S over
// |S| / 500 ppm (80 s for 40 ms) with no jump beyond the slewing bound. Left alone, the operator's
// events were corrected by S and the vehicle's not: every later latency off by S, unflagged.
// A step of the other board of known size S (|S| above this log's step threshold) is followed when,
// within 64 s (a daemon's poll) plus twice |S| / slew_ppm after it, d has moved its way from its
// median over the `2 * window` lines before by more than |S| / 2, or than the threshold plus
// slew_ppm / 2 over the time since the step (the follower slews at the bound; a crystal's drift stays
// far below it), at two lines in a row (one late printk is no follow), and this board has no step of
// its own (`own_steps`, kernel_log_clock's) in that time.
// Its stamps from the step until d is back within max(|S| / 16, 4 J, threshold) of that median plus S
// (two lines in a row, or the last) are flagged; from there on they are corrected by S, the bound
// the step's plus twice what was left. Never back: flagged to the end. origin "followed".
std::vector<store::ClockStep> kernel_log_followed(std::span<const store::ClockStep> other_steps,
                                                  std::span<const store::ClockStep> own_steps,
                                                  std::span<const std::int64_t> realtime_ns,
                                                  std::span<const std::int64_t> log_time_us,
                                                  const KernelLogStepOptions& options = {});

}  // namespace m2mlat::analysis
