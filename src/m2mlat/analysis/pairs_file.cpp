// The pairs file and the unmatched-events file of analysed scenarios.
#include "m2mlat/analysis/pairs_file.hpp"

#include <ostream>

#include "m2mlat/core/output_file.hpp"
#include "m2mlat/formats/import_file.hpp"

namespace m2mlat::analysis {

std::vector<formats::PairRow> pair_rows(std::span<const pairing::Pair> pairs) {
  std::vector<formats::PairRow> rows;
  rows.reserve(pairs.size());
  for (const pairing::Pair& p : pairs)
    rows.push_back({p.cause_index, p.effect_index, p.cause_time, p.effect_time, p.flags});
  return rows;
}

std::vector<pairing::Pair> pairs_from_rows(std::span<const formats::PairRow> rows) {
  std::vector<pairing::Pair> pairs;
  pairs.reserve(rows.size());
  for (const formats::PairRow& r : rows)
    pairs.push_back({r.cause_index, r.effect_index, r.cause_time, r.effect_time, r.flags});
  return pairs;
}

void write_pairs_file(const std::string& path, formats::Format format,
                      std::span<const ScenarioResult> results, const PairSessions& sessions) {
  // One table of rows for every scenario, reserved to its size and filled in place: a row is as large
  // as a pair, so a temporary table per scenario would hold the pairs a third time (at 10^7 pairs,
  // half a gigabyte more at the peak).
  std::vector<formats::PairRow> rows;
  std::size_t total = 0;
  for (const auto& r : results) total += r.match.pairs.size();
  rows.reserve(total);
  std::vector<formats::PairGroup> groups;
  std::vector<std::int64_t> session_column;
  session_column.reserve(total);
  UncertaintyColumns columns;
  bool any_clock = false;
  bool any_session = false;
  for (std::size_t k = 0; k < results.size(); ++k) {
    const auto& r = results[k];
    for (const pairing::Pair& p : r.match.pairs)
      rows.push_back({p.cause_index, p.effect_index, p.cause_time, p.effect_time,
                      p.flags | pair_flags(r.step_mark(p))});
    const std::size_t n = r.match.pairs.size();
    groups.push_back({r.input.scenario, r.input.cause_ref, r.input.effect_ref, n});
    append_columns(columns, r.uncertainty, r.match.pairs.size());
    any_clock |= !r.uncertainty.empty();
    if (k < sessions.sessions.size() && sessions.sessions[k].size() == n) {
      session_column.insert(session_column.end(), sessions.sessions[k].begin(), sessions.sessions[k].end());
      any_session = true;
    } else {
      session_column.insert(session_column.end(), n, 0);
    }
  }
  formats::PairExportOptions options;
  if (any_clock) {
    options.max_error_ns = columns.max_error_ns;
    options.u_ns = columns.u_ns;
    options.U95_ns = columns.U95_ns;
  }
  if (!results.empty())
    options.cause = results.front().input.cause_ref, options.effect = results.front().input.effect_ref;
  options.groups = groups;
  if (any_session) {
    options.sessions = session_column;
    options.labels = sessions.labels;
  }
  formats::export_pairs(path, format, rows, options);
}

void write_unmatched_file(const std::string& path, std::span<const ScenarioResult> results) {
  core::write_output_file(path, [&](std::ostream& out) {
    out << "scenario,side,node,channel,source_id,time_ns,reason\n";
    for (const auto& r : results)
      for (const auto& u : r.match.unmatched) {
        const bool cause = u.side == pairing::Side::cause;
        const auto& ref = cause ? r.input.cause_ref : r.input.effect_ref;
        out << r.input.scenario << ',' << pairing::to_string(u.side) << ',' << ref.node << ',' << ref.channel
            << ',' << r.seq(u) << ',' << u.time.ns() << ',' << pairing::to_string(u.reason) << '\n';
      }
  });
}

}  // namespace m2mlat::analysis
