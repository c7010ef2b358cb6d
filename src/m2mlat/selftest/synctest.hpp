// The synchronisation test: how far apart the two boards' clocks really are, measured with one
// pulse line wired to an input on both boards. Each board timestamps every edge on its own
// CLOCK_REALTIME; the same physical edge is paired across the boards (pairing/pulse_pairing.hpp) and
// offset = t_B - t_A (B's clock minus A's, plus the difference of the two interrupt latencies).
//
// The result: the offsets' statistics, signed and by magnitude (the reference study's table: count,
// mean, sd, min, max), percentiles, the jitter (successive differences of the offset), the
// time-transfer metrics ADEV/MDEV/TDEV/MTIE at tau = tau0 * 1, 2, 4, ... (stats/time_transfer.hpp),
// the offset over time, and beside it what the sync daemons claimed at each pulse: their own offset
// estimate (offset_B - offset_A of the nearest clock samples) and bound (max_error_A + max_error_B,
// analysis/uncertainty.hpp rules), with how often the measured offset stayed within that bound.
#pragma once

#include <cstddef>
#include <cstdint>
#include <nlohmann/json.hpp>
#include <optional>
#include <ostream>
#include <span>
#include <string>
#include <vector>

#include "m2mlat/analysis/uncertainty.hpp"
#include "m2mlat/core/time.hpp"
#include "m2mlat/formats/rig_sync.hpp"
#include "m2mlat/pairing/pulse_pairing.hpp"
#include "m2mlat/stats/time_transfer.hpp"

namespace m2mlat::selftest {

inline constexpr std::string_view kSyncTestFormat = "m2mlat-synctest/1";

// One pulse seen on both boards.
struct OffsetSample {
  std::int64_t t_ns = 0;                         // when: A's timestamp (or the rig file's trigger time), ns
  std::int64_t offset_ns = 0;                    // t_B - t_A, ns
  std::optional<std::int64_t> daemon_offset_ns;  // offset_B - offset_A of the daemons' samples
  std::optional<std::int64_t> daemon_bound_ns;   // max_error_A + max_error_B (kUnbounded: unsynchronised)
};

// Count, mean, sd (n - 1), min, max and percentiles of a set of ns values; NaN when undefined.
struct ValueStats {
  std::size_t n = 0;
  double mean_ns = 0, sd_ns = 0, min_ns = 0, max_ns = 0;
  std::vector<std::pair<double, double>> percentiles;  // (percent, ns), type-7 quantiles
};
ValueStats value_stats(std::span<const std::int64_t> values_ns, std::span<const double> percents);

struct SyncTestOptions {
  core::Duration tau0{0};  // the sample interval of the time-transfer metrics; 0: the median spacing
  std::vector<double> percentiles{1, 5, 25, 50, 75, 95, 99};
  std::size_t max_factors = 24;  // tau factors 1, 2, 4, ... at most this many
};

struct SyncTestResult {
  std::string source;                            // what was measured (files, nodes), for the reader
  std::vector<OffsetSample> series;              // by time
  std::size_t unmatched_a = 0, unmatched_b = 0;  // edges seen on one board only
  core::Duration period{0};                      // the pulse period the pairing used (0: not paired here)
  core::Duration tau0{0};                        // the metrics' sample interval
  std::size_t gaps = 0;                          // intervals longer than 1.5 tau0 (lost pulses)
  ValueStats offset;                             // t_B - t_A
  ValueStats abs_offset;                         // |t_B - t_A|
  ValueStats jitter;                             // successive differences of the offset
  ValueStats abs_jitter;                         // their magnitude
  std::vector<stats::StabilityPoint> stability;
  // The daemons' view, over the pulses where both boards had clock samples.
  std::size_t daemon_samples = 0;
  ValueStats daemon_error;              // measured offset - daemon offset estimate
  std::size_t within_daemon_bound = 0;  // |measured offset| <= daemon bound
};

// The statistics of a series already paired (any order; sorted by t here).
SyncTestResult analyse_offsets(std::vector<OffsetSample> series, const SyncTestOptions& options = {});

// From the two boards' edge times (ns, same clock), with each board's clock samples if known (empty
// tracks: no daemon comparison).
SyncTestResult synctest_from_edges(std::span<const std::int64_t> a_ns, std::span<const std::int64_t> b_ns,
                                   const analysis::ClockTrack& a_clock, const analysis::ClockTrack& b_clock,
                                   const pairing::PulsePairingOptions& pairing_options,
                                   const SyncTestOptions& options = {}, double growth_ppm = 15);

// From the reference rig's sync CSV: its offsets as written, at its trigger times.
SyncTestResult synctest_from_rig(const formats::SyncImport& rig, const SyncTestOptions& options = {});

// {"format":"m2mlat-synctest/1", ...}: everything above; the series only with `with_series`.
nlohmann::json synctest_json(const SyncTestResult& result, bool with_series);
// t_ns,offset_ns,daemon_offset_ns,daemon_bound_ns (empty when unknown), one row per pulse.
void write_series_csv(std::ostream& out, const SyncTestResult& result);

}  // namespace m2mlat::selftest
