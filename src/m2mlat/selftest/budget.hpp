// The error budget: how far a measured latency can be from the true one, term by term.
//
//   E_sync     the two boards' clock disagreement: from a synchronisation test (synctest.hpp: by
//              default its mean |offset|, as the reference study quoted it; or P95 / max |offset|),
//              or the daemons' live bounds in a store, or a given value
//   E_kernel   the timestamping asymmetry: each board stamps an edge 0 .. L late (L its scheduling /
//              interrupt latency from cyclictest or the schedtest), so the difference of the two
//              delays lies in [-L_A, L_B] and its worst magnitude is max(L_A, L_B)
//   E_circuit  the sensor and input circuit (Hall switch A3144: about 2 us output switching time)
//   E_calib    where on each wheel the sensor fires: a misalignment of d degrees at a steering rate
//              of w deg/s is d / w seconds. The rate is given, or measured in a store from a wheel
//              with several magnets: the known angle between neighbouring magnets divided by the
//              time between their consecutive edges (the median over all such edge pairs)
//   E_onset    in place of E_calib when the motion source is inertial (a gyroscope per wheel): the
//              measured onset term, from an onset test (onsettest.hpp, `m2mlat onsettest`): for the
//              chosen detector, the 95th percentile of |onset error| of the hand plus that of the
//              actuator (each side's onset off by its worst in the same direction), in one speed class
//              or the worst of them. Not assumed: measured on the simulator's truth.
//
// Each term has two numbers, as every sample's uncertainty has (analysis/uncertainty.hpp, one story:
// docs/precision.md): its worst case (value_ns, the budget's quoted figure) and its standard
// uncertainty u (k = 1). A term given as a bound is uniform within it: u = bound / sqrt(3) (sync
// given, circuit, calibration); the kernel's two stamp delays are each uniform in [0, L]: u =
// sqrt((L_A^2 + L_B^2) / 12); a synchronisation test's u is its offsets' RMS (sqrt(mean^2 + sd^2)),
// a store's the daemons' own est_error (root sum of squares of the two boards' medians); an onset
// test's u is sqrt(p95_hand^2 + p95_actuator^2) / 1.96 (each |error|'s P95 about 1.96 sd).
//
// total_ns is the worst case, the plain sum of the terms; u_ns the root sum of squares of the terms'
// u (independent terms), and the expanded uncertainty U95 = 2 u (k = 2, about 95 %).
#pragma once

#include <cstdint>
#include <nlohmann/json.hpp>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "m2mlat/core/time.hpp"

namespace m2mlat::selftest {

inline constexpr std::string_view kBudgetFormat = "m2mlat-budget/2";
inline constexpr std::int64_t kA3144SwitchingNs = 2'000;  // A3144 output rise/fall time, about 2 us

struct BudgetTerm {
  std::string name;  // "sync", "kernel", "circuit", "calibration", "onset"
  std::int64_t value_ns = 0;  // the worst case
  std::string source;  // where the value came from, e.g. "synctest co.json: mean |offset|"
  double u_ns = 0;     // the standard uncertainty (k = 1), ns
};

// A term given as a bound (uniform within it): u = bound / sqrt(3).
BudgetTerm bound_term(std::string name, std::int64_t bound_ns, std::string source);

struct Budget {
  std::vector<BudgetTerm> terms;
  std::int64_t total_ns = 0;  // the worst case: the sum of the terms
  double u_ns = 0;            // the standard uncertainty: root sum of squares of the terms' u
  double expanded_ns() const { return 2 * u_ns; }  // U95 (k = 2)
};

Budget make_budget(std::vector<BudgetTerm> terms);

// E_kernel from the two boards' worst scheduling latencies (ns): max(a, b).
BudgetTerm kernel_term(core::Duration worst_a, core::Duration worst_b, std::string source);
// E_calib = misalignment / rate, rounded to ns. Throws core::Error(usage) unless rate > 0 and
// misalignment >= 0.
BudgetTerm calibration_term(double misalignment_deg, double rate_deg_s, std::string source);
// The wheel's rate from consecutive edges of one channel (sorted ns): the angle between magnets
// divided by each interval shorter than `max_gap` (longer ones are between manoeuvres); the median
// rate, deg/s. nullopt when no interval qualifies.
struct RateEstimate {
  double median_deg_s = 0;
  double p5_deg_s = 0;  // a slow manoeuvre: the calibration error is larger
  std::size_t intervals = 0;
};
std::optional<RateEstimate> steering_rate(std::span<const std::int64_t> edges_ns, double magnet_angle_deg,
                                          core::Duration max_gap, core::Duration min_gap);

// E_sync from a synctest JSON document (selftest::synctest_json): `statistic` is "mean_abs",
// "p95_abs" or "max_abs". Throws core::Error(data) naming `name` when a field is missing.
BudgetTerm sync_term_from_synctest(const nlohmann::json& doc, const std::string& statistic,
                                   const std::string& name);

// E_onset from an m2mlat-onsettest/1 document (onsettest_json): `detector` ("flank", "reference"),
// `speed` a speed class name ("slow", "medium", "fast") or "worst" (the class with the largest term).
// Throws core::Error(data) naming `name` and the field when the document lacks it (the detector, a
// class's hand or actuator row), core::Error(usage) for an unknown speed.
BudgetTerm onset_term_from_onsettest(const nlohmann::json& doc, const std::string& detector,
                                     const std::string& speed, const std::string& name);

nlohmann::json budget_json(const Budget& budget);

}  // namespace m2mlat::selftest
