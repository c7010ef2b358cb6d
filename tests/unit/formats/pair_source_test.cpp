// The pairs writers reading their rows from a source a block at a time: the same bytes as from rows
// held whole, over more rows than one block, with groups, sessions and uncertainty columns that
// cross the blocks' edges.
#include "m2mlat/formats/pair_source.hpp"

#include <gtest/gtest.h>

#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include "m2mlat/core/error.hpp"
#include "m2mlat/formats/pair_rows_source.hpp"
#include "m2mlat/formats/pairs_export.hpp"
#include "m2mlat/formats/rig_paired.hpp"

namespace m2mlat::formats {
namespace {

// Three blocks and a part of a fourth.
constexpr std::size_t kRows = 3 * kPairBlockRows + 123;

// The rows and per-pair columns held whole: what the span entry points take.
struct Table {
  std::vector<PairRow> rows;
  std::vector<std::int64_t> sessions;
  std::vector<std::optional<std::int64_t>> max_error_ns, u_ns, U95_ns;
};

Table make_table() {
  Table t;
  for (std::size_t i = 0; i < kRows; ++i) {
    const auto n = static_cast<std::int64_t>(i);
    const auto at = [](std::int64_t ns) { return core::TimePoint::from_ns(core::Clock::realtime, ns); };
    // Latencies of both signs and of odd sizes, so that the ms text varies.
    t.rows.push_back({n, n + 1, at(1'762'872'545'000'000'000 + n * 1'000'003),
                      at(1'762'872'545'000'000'000 + n * 1'000'003 + (n % 7 == 0 ? -n : n * 4'111)),
                      static_cast<std::uint32_t>(n % 5)});
    t.sessions.push_back(n % 3);  // 0: unknown
    const bool known = n % 11 != 0;
    t.max_error_ns.push_back(known ? std::optional(n * 10) : std::nullopt);
    t.u_ns.push_back(known ? std::optional(n * 2) : std::nullopt);
    t.U95_ns.push_back(known ? std::optional(n * 4) : std::nullopt);
  }
  return t;
}

// A source that makes each row when asked (as analysis::write_pairs_file's does), and records how
// it was asked.
class MadeRows final : public PairSource {
 public:
  explicit MadeRows(const Table& table, PairColumns columns) : table_(table), columns_(columns) {}
  std::size_t size() const override { return table_.rows.size(); }
  PairColumns columns() const override { return columns_; }
  void fill(std::size_t first, std::span<PairRecord> out) const override {
    EXPECT_EQ(first, next_);  // in order, none skipped or read twice
    EXPECT_LE(out.size(), kPairBlockRows);
    for (std::size_t j = 0; j < out.size(); ++j) {
      const std::size_t i = first + j;
      out[j] = {table_.rows[i], table_.sessions[i], table_.max_error_ns[i], table_.u_ns[i], table_.U95_ns[i], true, {}, std::nullopt};
    }
    next_ = first + out.size();
    ++calls_;
  }
  std::size_t calls() const { return calls_; }
  std::size_t next() const { return next_; }

 private:
  const Table& table_;
  PairColumns columns_;
  mutable std::size_t next_ = 0, calls_ = 0;
};

// Three scenarios, of sizes that end mid-block and on a block's edge.
const std::vector<PairGroup>& groups() {
  static const std::vector<PairGroup> g{{"first", {"op", "wheel"}, {"veh", "wheel"}, kPairBlockRows - 1},
                                        {"second, quoted", {"st", "pedal, left"}, {"car", "pedal"}, 1},
                                        {"third", {"op", "wheel"}, {"veh", "wheel"}, kRows - kPairBlockRows}};
  return g;
}

TEST(PairSource, CsvJsonlAndRigAsFromTheSpan) {
  const Table table = make_table();
  PairExportOptions options;
  options.groups = groups();
  options.labels = {{1, "run 1"}, {2, "run \"2\""}};
  PairExportOptions span_options = options;
  span_options.sessions = table.sessions;
  span_options.max_error_ns = table.max_error_ns;
  span_options.u_ns = table.u_ns;
  span_options.U95_ns = table.U95_ns;

  {
    const MadeRows source(table, {true, true, true});
    std::ostringstream from_source, from_span;
    write_pairs_csv(from_source, source, options);
    write_pairs_csv(from_span, table.rows, span_options);
    EXPECT_EQ(source.calls(), 4u);
    EXPECT_EQ(source.next(), kRows);
    EXPECT_EQ(from_source.str(), from_span.str());
    EXPECT_NE(from_source.str().find("\"second, quoted\","), std::string::npos);
  }
  {
    const MadeRows source(table, {true, true, true});
    std::ostringstream from_source, from_span;
    write_pairs_jsonl(from_source, source, options);
    write_pairs_jsonl(from_span, table.rows, span_options);
    EXPECT_EQ(source.calls(), 4u);
    EXPECT_EQ(from_source.str(), from_span.str());
  }
  {
    const MadeRows source(table, {});
    std::ostringstream from_source, from_span;
    write_rig_paired_csv(from_source, source);
    write_rig_paired_csv(from_span, table.rows);
    EXPECT_EQ(source.calls(), 4u);
    EXPECT_EQ(from_source.str(), from_span.str());
  }
}

TEST(PairSource, OnlyTheSourcesColumnsAreWritten) {
  const Table table = make_table();
  PairExportOptions span_options;
  span_options.sessions = table.sessions;
  span_options.u_ns = table.u_ns;
  const MadeRows source(table, {false, true, false});
  std::ostringstream from_source, from_span;
  write_pairs_csv(from_source, source, {});
  write_pairs_csv(from_span, table.rows, span_options);
  EXPECT_EQ(from_source.str(), from_span.str());
  EXPECT_NE(from_source.str().find(",latency_ms,u_ns,pair_flags\n"), std::string::npos);
}

TEST(PairSource, ChecksKeepTheirErrors) {
  const Table table = make_table();
  const MadeRows source(table, {});
  std::ostringstream out;
  const std::vector<PairGroup> too_few{{"a", {"op", "w"}, {"veh", "w"}, kRows - 1}};
  PairExportOptions options;
  options.groups = too_few;
  EXPECT_THROW(write_pairs_csv(out, source, options), core::Error);
  const std::vector<PairGroup> broken{{"a\nb", {"op", "w"}, {"veh", "w"}, kRows}};
  options.groups = broken;
  EXPECT_THROW(write_pairs_jsonl(out, source, options), core::Error);
  options.groups = {};
  options.labels = {{1, "two\nlines"}};
  EXPECT_THROW(write_pairs_csv(out, source, options), core::Error);
  EXPECT_EQ(source.calls(), 0u);  // nothing read before the checks
  // The span path's own check: a column of another length than the rows.
  const std::vector<std::optional<std::int64_t>> short_column(kRows - 1);
  PairExportOptions span_options;
  span_options.max_error_ns = short_column;
  EXPECT_THROW(PairRowsSource(table.rows, span_options), core::Error);
  EXPECT_THROW(write_pairs_csv(out, table.rows, span_options), core::Error);
}

TEST(PairSource, EmptySourceWritesTheHeaderOnly) {
  const Table empty;
  const MadeRows source(empty, {true, true, true});
  std::ostringstream out;
  write_pairs_csv(out, source, {});
  EXPECT_EQ(source.calls(), 0u);
  EXPECT_EQ(out.str().find('\n'), out.str().size() - 1);
}

}  // namespace
}  // namespace m2mlat::formats
