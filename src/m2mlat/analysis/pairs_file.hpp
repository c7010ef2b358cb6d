// The pairing of analysed scenarios in files: the pairs (m2mlat-pairs/4 CSV or JSON Lines, or the
// reference rig's paired CSV) with each pair's uncertainty columns, and the unmatched events with
// their reasons. The matcher's pairs and formats' own rows are converted here (both ways), so
// formats/ never depends on pairing; `m2mlat pair` and `m2mlat export --what pairs` write through
// this file, and a paired CSV taken as given is read into pairs through it.
#pragma once

#include <span>
#include <string>
#include <vector>

#include "m2mlat/analysis/pair_sessions.hpp"
#include "m2mlat/analysis/scenario_result.hpp"
#include "m2mlat/formats/format.hpp"
#include "m2mlat/formats/pair_row.hpp"
#include "m2mlat/pairing/pair.hpp"

namespace m2mlat::analysis {

// A file's rows as pairs (indices and flags as they are). A pair holds no times: the caller keeps the
// rows' times in columns at those indices (and their clock).
std::vector<pairing::Pair> pairs_from_rows(std::span<const formats::PairRow> rows);

// Writes the pairs of every result, one scenario after another, to `path` ("-" = standard output,
// atomically otherwise) as `format` (pairs_csv, pairs_jsonl or rig_paired_csv; another format is
// core::Error(usage)). Each row names its scenario and that scenario's nodes and channels, and its
// session and label from `sessions` (pair_sessions.hpp; empty: unknown); the max_error_ns, u_ns and
// U95_ns columns are written when any result has clock samples. The pairs become rows a block at a
// time (formats/pair_source.hpp): no copy of them, nor any per-pair column, is built beside them.
void write_pairs_file(const std::string& path, formats::Format format,
                      std::span<const ScenarioResult> results, const PairSessions& sessions = {});

// Writes the unmatched events of every result as CSV: scenario, side, node, channel, source id
// (store seq or file index), time (ns) and reason (pairing::UnmatchedReason's name).
void write_unmatched_file(const std::string& path, std::span<const ScenarioResult> results);

}  // namespace m2mlat::analysis
