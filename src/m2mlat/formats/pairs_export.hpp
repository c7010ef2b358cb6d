// Exporting matched cause -> effect pairs as CSV or JSON Lines (format m2mlat-pairs/4).
//
//   scenario,session,label,cause_node,cause_channel,effect_node,effect_channel,clock,cause_time_ns,
//     effect_time_ns,latency_ns,latency_ms,max_error_ns,u_ns,U95_ns,pair_flags,in_statistics,left_out
//   static_5g,1,run-1,operator,wheel,vehicle,wheel,realtime,1762872545550296135,1762872546417585462,
//     867289327,867.289327,12250000,160000,320000,0,true,
//
// (one line each in the file; the header comes first, no comment line: pandas, R and DuckDB read it
// as it is). scenario is the scenario's name; session and label are the cause event's session in the
// store (empty when the pairs come from files). Times are integer ns on `clock`; latency_ns =
// effect_time_ns - cause_time_ns exactly, and latency_ms is the same value as exact decimal text
// (core::format_ms: always 6 decimals). Optional columns follow, each when the caller gives it
// (integer ns; empty / null when unknown; analysis/uncertainty.hpp defines them): max_error_ns (the
// worst-case bound on the latency's error), u_ns (its standard uncertainty, k = 1), U95_ns (the
// expanded uncertainty, k = 2); then pair_flags (PairRow::flags, pairing::PairFlag bits, decimal;
// written unless switched off; not "flags", which pandas' DataFrame has as its own attribute, nor the
// events files' flag_bits, whose bits mean other things); then, when the source knows them,
// in_statistics (true / false: whether the scenario's statistics hold the pair) and left_out (why not:
// ambiguous, competing, jump, bounced, improbable, after_clock_step or sync_gated; empty / null when it
// is in); then, when a scenario was paired by the alignment model, probability (its posterior). In JSON Lines each pair is one object with the same members and "format":"m2mlat-pairs/4";
// latency_ms is written as a JSON number with the exact decimal text. (m2mlat-pairs/3 named
// pair_flags flag_bits and had no in_statistics, left_out; m2mlat-pairs/2 began with "# format:
// m2mlat-pairs/2", had no scenario, session, label, and named the flags "flags"; m2mlat-pairs/1 had
// uncertainty_ns = max_error_ns and est_error_ns.)
//
// For comparison with the reference rig's scripts, see write_rig_paired_csv in rig_paired.hpp.
#pragma once

#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <ostream>
#include <span>
#include <string_view>

#include "m2mlat/core/event.hpp"
#include "m2mlat/formats/pair_row.hpp"
#include "m2mlat/formats/pair_source.hpp"

namespace m2mlat::formats {

inline constexpr std::string_view kPairsFormat = "m2mlat-pairs/4";

// A run of consecutive pairs of one scenario, with where its causes and effects were measured.
struct PairGroup {
  std::string scenario;
  core::ChannelRef cause, effect;
  std::size_t count = 0;  // pairs in the run
};

struct PairExportOptions {
  // Used when `groups` is empty: every pair is of this scenario, measured there.
  std::string scenario;
  core::ChannelRef cause{"operator", "wheel"};  // where the cause edges were measured
  core::ChannelRef effect{"vehicle", "wheel"};  // where the effect edges were measured
  std::span<const PairGroup> groups;  // in pair order, counting every pair; empty: the three above
  // The sessions' labels by id (a row's session is its PairRecord::session).
  std::map<std::int64_t, std::string> labels;
  // The per-pair columns of the span entry points (a PairSource carries its own and ignores these).
  // The store session of each pair's cause event (0 = unknown); empty: the session and label columns
  // are empty.
  std::span<const std::int64_t> sessions;
  // Each empty: no such column. Otherwise one entry per pair (nullopt = unknown), ns.
  std::span<const std::optional<std::int64_t>> max_error_ns;  // the worst-case bound
  std::span<const std::optional<std::int64_t>> u_ns;          // the standard uncertainty (k = 1)
  std::span<const std::optional<std::int64_t>> U95_ns;        // the expanded uncertainty (k = 2)
  // Why each pair is not in the statistics ("" when it is); empty: no in_statistics, left_out columns.
  std::span<const std::string_view> left_out;
  // Write the flags column (PairRow::flags, pairing::PairFlag bits, e.g. 1 = ambiguous burst).
  bool flags = true;
};

// Both read the rows a block at a time (pair_source.hpp) and throw core::Error(internal) if the
// groups do not count the source's rows, and core::Error(data) for an empty node or channel name, or
// a name or label with a line break.
void write_pairs_csv(std::ostream& out, const PairSource& pairs, const PairExportOptions& options);
void write_pairs_jsonl(std::ostream& out, const PairSource& pairs, const PairExportOptions& options);
// The same for rows held whole, with options' per-pair columns; also core::Error(internal) if a
// non-empty column does not have one entry per pair.
void write_pairs_csv(std::ostream& out, std::span<const PairRow> pairs, const PairExportOptions& options);
void write_pairs_jsonl(std::ostream& out, std::span<const PairRow> pairs, const PairExportOptions& options);

}  // namespace m2mlat::formats
