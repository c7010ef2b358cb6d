// The pairs file and the unmatched-events file of analysed scenarios.
#include "m2mlat/analysis/pairs_file.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <limits>
#include <ostream>

#include "m2mlat/core/error.hpp"
#include "m2mlat/core/output_file.hpp"
#include "m2mlat/formats/import_file.hpp"
#include "m2mlat/formats/pair_source.hpp"

namespace m2mlat::analysis {

namespace {

// Whether result k's sessions are known: only when there is one per pair (pair_sessions.hpp).
bool sessions_known(const PairSessions& sessions, std::size_t k, std::size_t pairs) {
  return k < sessions.sessions.size() && sessions.sessions[k].size() == pairs;
}

// The pairs of every result, one scenario after another, as the rows of a pairs file: each row made
// when the writer asks for its block, from the pair, its clock-step mark, its cause's session and its
// uncertainty.
class ResultPairs final : public formats::PairSource {
 public:
  ResultPairs(std::span<const ScenarioResult> results, const PairSessions& sessions, bool with_uncertainty)
      : results_(results), with_uncertainty_(with_uncertainty) {
    for (const auto& r : results) with_probability_ |= !r.match.probability.empty();
    starts_.reserve(results.size() + 1);
    starts_.push_back(0);
    for (std::size_t k = 0; k < results.size(); ++k) {
      const std::size_t n = results[k].match.pairs.size();
      starts_.push_back(starts_.back() + n);
      sessions_.push_back(sessions_known(sessions, k, n) ? std::span<const std::int64_t>(sessions.sessions[k])
                                : std::span<const std::int64_t>());
    }
  }

  std::size_t size() const override { return starts_.back(); }
  formats::PairColumns columns() const override {
    return {with_uncertainty_, with_uncertainty_, with_uncertainty_, true, with_probability_};
  }

  void fill(std::size_t first, std::span<formats::PairRecord> out) const override {
    // The result that holds row `first`: the last one starting at or before it (empty ones skipped).
    auto k =
        static_cast<std::size_t>(std::upper_bound(starts_.begin(), starts_.end(), first) - starts_.begin()) -
        1;
    for (std::size_t j = 0; j < out.size(); ++j) {
      const std::size_t row = first + j;
      while (row >= starts_[k + 1]) ++k;
      const ScenarioResult& r = results_[k];
      const std::size_t i = row - starts_[k];
      const pairing::Pair& p = r.match.pairs[i];
      formats::PairRecord& record = out[j];
      const auto times = r.times();
      record.row = {p.cause_index, p.effect_index, core::TimePoint::from_ns(r.match.clock, times.cause(p)),
                    core::TimePoint::from_ns(r.match.clock, times.effect(p)),
                    p.flags | pair_flags(r.step_mark(p))};
      record.session = sessions_[k].empty() ? 0 : sessions_[k][i];
      record.left_out = r.left_out(i);
      record.in_statistics = record.left_out.empty();
      record.probability = i < r.match.probability.size() ? std::optional(r.match.probability[i]) : std::nullopt;
      // Unknown or unbounded uncertainty, and pairs past the end of it, are written empty.
      const bool bounded = i < r.uncertainty.size() && r.uncertainty[i].bounded();
      record.max_error_ns = bounded ? std::optional(r.uncertainty[i].max_error_ns) : std::nullopt;
      record.u_ns = bounded ? std::optional(r.uncertainty[i].u_ns) : std::nullopt;
      record.U95_ns = bounded ? std::optional(r.uncertainty[i].expanded_ns()) : std::nullopt;
    }
  }

 private:
  std::span<const ScenarioResult> results_;
  bool with_uncertainty_;
  bool with_probability_ = false;  // a result paired by the alignment model
  std::vector<std::size_t> starts_;                      // the first row of each result, then the total
  std::vector<std::span<const std::int64_t>> sessions_;  // per result: one per pair, or empty
};

}  // namespace

std::vector<pairing::Pair> pairs_from_rows(std::span<const formats::PairRow> rows) {
  std::vector<pairing::Pair> pairs;
  pairs.reserve(rows.size());
  // A pair's indices are 32 bits (pairing::Pair); a file's rows number theirs from 0.
  const auto index = [](std::int64_t value, std::size_t row, const char* field) {
    if (value < 0 || value > std::numeric_limits<std::uint32_t>::max())
      throw core::Error(
          core::ErrorKind::data,
          fmt::format("pair row {}: field '{}' {} is outside 0 .. 2^32 - 1", row + 1, field, value));
    return static_cast<std::uint32_t>(value);
  };
  for (std::size_t k = 0; k < rows.size(); ++k) {
    const formats::PairRow& r = rows[k];
    pairs.push_back(
        {index(r.cause_index, k, "cause_index"), index(r.effect_index, k, "effect_index"), r.flags});
  }
  return pairs;
}

void write_pairs_file(const std::string& path, formats::Format format,
                      std::span<const ScenarioResult> results, const PairSessions& sessions) {
  // The pairs are not copied: the writer takes them as rows a block at a time (ResultPairs). Per
  // scenario only its group (names and count) is kept here.
  std::vector<formats::PairGroup> groups;
  bool any_clock = false;
  bool any_session = false;
  for (std::size_t k = 0; k < results.size(); ++k) {
    const auto& r = results[k];
    const std::size_t n = r.match.pairs.size();
    groups.push_back({r.input.scenario, r.input.cause_ref, r.input.effect_ref, n});
    any_clock |= !r.uncertainty.empty();
    any_session |= sessions_known(sessions, k, n);
  }
  formats::PairExportOptions options;
  if (!results.empty())
    options.cause = results.front().input.cause_ref, options.effect = results.front().input.effect_ref;
  options.groups = groups;
  if (any_session) options.labels = sessions.labels;
  formats::export_pairs(path, format, ResultPairs(results, sessions, any_clock), options);
}

void write_unmatched_file(const std::string& path, std::span<const ScenarioResult> results) {
  core::write_output_file(path, [&](std::ostream& out) {
    out << "scenario,side,node,channel,source_id,time_ns,reason\n";
    for (const auto& r : results)
      for (const auto& u : r.match.unmatched) {
        const bool cause = u.side == pairing::Side::cause;
        const auto& ref = cause ? r.input.cause_ref : r.input.effect_ref;
        const auto& times = cause ? r.input.cause.t_ns : r.input.effect.t_ns;  // the paired columns
        out << r.input.scenario << ',' << pairing::to_string(u.side) << ',' << ref.node << ',' << ref.channel
            << ',' << r.seq(u) << ',' << times[u.index] << ',' << pairing::to_string(u.reason) << '\n';
      }
  });
}

}  // namespace m2mlat::analysis
