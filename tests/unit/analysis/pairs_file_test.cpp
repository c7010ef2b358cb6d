// analysis::write_pairs_file takes the scenarios' pairs as rows a block at a time: its files are the
// bytes of the same rows and columns held whole and written through the span entry point, over
// scenarios that end mid-block, an empty one, sessions known for some, uncertainty for some (shorter
// than the pairs for one) and clock-step marks.
#include "m2mlat/analysis/pairs_file.hpp"

#include <gtest/gtest.h>

#include <fstream>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include "m2mlat/analysis/clock_steps.hpp"
#include "m2mlat/core/error.hpp"
#include "m2mlat/formats/import_file.hpp"
#include "m2mlat/formats/pair_source.hpp"
#include "temp_dir.hpp"

namespace m2mlat::analysis {
namespace {

std::string read_text(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

ScenarioResult make_result(const std::string& name, std::size_t pairs, std::int64_t start_ns) {
  ScenarioResult r;
  r.input.scenario = name;
  r.input.cause_ref = {"op-" + name, "wheel"};
  r.input.effect_ref = {"veh-" + name, "wheel"};
  // Two effects before the first pair's: a pair's indices need not be equal.
  r.input.effect.t_ns = {start_ns - 2, start_ns - 1};
  for (std::size_t i = 0; i < pairs; ++i) {
    const auto n = static_cast<std::int64_t>(i);
    pairing::Pair p;
    p.cause_index = static_cast<std::uint32_t>(n);
    p.effect_index = static_cast<std::uint32_t>(n + 2);
    r.input.cause.t_ns.push_back(start_ns + n * 1'000'033);
    r.input.effect.t_ns.push_back(r.input.cause.t_ns.back() + 900'000'000 + n * 17);
    p.flags = n % 13 == 0 ? std::uint32_t{pairing::kPairAmbiguous} : 0u;
    r.match.pairs.push_back(p);
  }
  return r;
}

// Known, unknown and unbounded samples in turn.
std::vector<SampleUncertainty> make_uncertainty(std::size_t n) {
  std::vector<SampleUncertainty> samples(n);
  for (std::size_t i = 0; i < n; ++i) {
    const auto v = static_cast<std::int64_t>(i);
    if (i % 7 == 3) samples[i].flags = kUncertaintyNoClock;
    samples[i].max_error_ns = i % 9 == 4 ? kUnbounded : 1'000 + v;
    samples[i].u_ns = 100 + v;
  }
  return samples;
}

// What write_pairs_file wrote before it read its rows block by block: the whole table and columns.
void write_whole(const std::string& path, formats::Format format, std::span<const ScenarioResult> results,
                 const PairSessions& sessions) {
  std::vector<formats::PairRow> rows;
  std::vector<formats::PairGroup> groups;
  std::vector<std::int64_t> session_column;
  std::vector<std::optional<std::int64_t>> max_error, u, expanded;
  std::vector<std::string_view> left_out;
  bool any_clock = false, any_session = false;
  for (std::size_t k = 0; k < results.size(); ++k) {
    const auto& r = results[k];
    const std::size_t n = r.match.pairs.size();
    for (std::size_t i = 0; i < n; ++i) {
      const auto& p = r.match.pairs[i];
      rows.push_back({p.cause_index, p.effect_index,
                      core::TimePoint::from_ns(r.match.clock, r.times().cause(p)),
                      core::TimePoint::from_ns(r.match.clock, r.times().effect(p)),
                      p.flags | pair_flags(r.step_mark(p))});
      const bool bounded = i < r.uncertainty.size() && r.uncertainty[i].bounded();
      max_error.push_back(bounded ? std::optional(r.uncertainty[i].max_error_ns) : std::nullopt);
      u.push_back(bounded ? std::optional(r.uncertainty[i].u_ns) : std::nullopt);
      expanded.push_back(bounded ? std::optional(r.uncertainty[i].expanded_ns()) : std::nullopt);
      left_out.push_back(r.left_out(i));
      const bool known = k < sessions.sessions.size() && sessions.sessions[k].size() == n;
      session_column.push_back(known ? sessions.sessions[k][i] : 0);
      any_session |= known;
    }
    groups.push_back({r.input.scenario, r.input.cause_ref, r.input.effect_ref, n});
    any_clock |= !r.uncertainty.empty();
  }
  formats::PairExportOptions options;
  options.cause = results.front().input.cause_ref;
  options.effect = results.front().input.effect_ref;
  options.groups = groups;
  options.left_out = left_out;
  if (any_clock) options.max_error_ns = max_error, options.u_ns = u, options.U95_ns = expanded;
  if (any_session) options.sessions = session_column, options.labels = sessions.labels;
  formats::export_pairs(path, format, rows, options);
}

TEST(PairsFile, BlockByBlockAsFromTheWholeTable) {
  const std::size_t block = formats::kPairBlockRows;
  std::vector<ScenarioResult> results;
  results.push_back(make_result("a", block + 5, 1'762'872'545'000'000'000));
  results.push_back(make_result("empty", 0, 0));
  results.push_back(make_result("b", 2 * block - 7, 1'762'900'000'000'000'000));
  results.push_back(make_result("c", 300, 1'763'000'000'000'000'000));
  results[0].uncertainty = make_uncertainty(results[0].match.pairs.size());
  results[3].uncertainty = make_uncertainty(200);  // pairs past its end: unknown
  // Clock-step marks on some of b's events: their pairs carry the step flags.
  auto& marks = results[2].steps.cause.mark;
  marks.assign(results[2].match.pairs.size(), StepMark::none);
  for (std::size_t i = 0; i < marks.size(); i += 97)
    marks[i] = i % 2 ? StepMark::corrected : StepMark::unknown;

  PairSessions sessions;
  sessions.sessions.resize(4);
  for (std::size_t i = 0; i < results[2].match.pairs.size(); ++i)
    sessions.sessions[2].push_back(static_cast<std::int64_t>(i % 4));  // 0: unknown
  sessions.sessions[3].assign(5, 1);                                   // not one per pair: not used
  sessions.labels = {{1, "first, run"}, {2, "second"}};

  const testing::TempDir temp;
  std::size_t compared = 0;
  for (const auto format :
       {formats::Format::pairs_csv, formats::Format::pairs_jsonl, formats::Format::rig_paired_csv}) {
    for (const bool with_sessions : {true, false}) {
      const PairSessions& given = with_sessions ? sessions : PairSessions{};
      const std::string blocks = temp.file("blocks"), whole = temp.file("whole");
      write_pairs_file(blocks, format, results, given);
      write_whole(whole, format, results, given);
      const std::string text = read_text(blocks);
      EXPECT_EQ(text, read_text(whole)) << formats::to_string(format) << " sessions " << with_sessions;
      EXPECT_GT(text.size(), 3 * block * 40);
      ++compared;
    }
  }
  EXPECT_EQ(compared, 6u);
}

// A file's rows become pairs with their indices and flags as they are; one outside a pair's 32 bits is
// refused by row and field, not wrapped.
TEST(PairsFile, RowsBecomePairsAndAnIndexBeyond32BitsIsRefused) {
  const auto t = core::TimePoint::from_ns(core::Clock::realtime, 1'762'872'545'000'000'000);
  std::vector<formats::PairRow> rows{{0, 1, t, t + core::Duration{800'000'000}, 1},
                                     {4'294'967'295, 2, t, t + core::Duration{700'000'000}, 0}};
  const auto pairs = pairs_from_rows(rows);
  ASSERT_EQ(pairs.size(), 2u);
  EXPECT_EQ(pairs[0].effect_index, 1u);
  EXPECT_EQ(pairs[0].flags, 1u);
  EXPECT_EQ(pairs[1].cause_index, 4'294'967'295u);
  for (const std::int64_t bad : {std::int64_t{-1}, std::int64_t{4'294'967'296}}) {
    rows[1].effect_index = bad;
    try {
      pairs_from_rows(rows);
      ADD_FAILURE() << bad << " was taken";
    } catch (const core::Error& e) {
      EXPECT_NE(std::string(e.what()).find("pair row 2: field 'effect_index'"), std::string::npos)
          << e.what();
    }
  }
}

}  // namespace
}  // namespace m2mlat::analysis
