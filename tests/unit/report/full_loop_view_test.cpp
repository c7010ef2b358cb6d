// The full-loop files in the report: the table rows with their exclusions, the JSON and CSV layout,
// the figure's boxes (M2M, G2G, E2E per file), the HTML section, the pgfplots figure, and the
// comparisons of two files quantity by quantity.
#include "m2mlat/report/full_loop_view.hpp"

#include <gtest/gtest.h>

#include <fstream>
#include <sstream>

#include "m2mlat/core/error.hpp"
#include "m2mlat/report/html_report.hpp"
#include "m2mlat/report/pgfplots.hpp"
#include "m2mlat/report/report_model.hpp"
#include "m2mlat/report/report_tables.hpp"
#include "temp_dir.hpp"

namespace m2mlat::report::full_loop_view_test {
namespace {

using analysis::LoopQuantity;
constexpr std::int64_t kMs = 1'000'000;
constexpr std::int64_t kT0 = 1'762'872'545'000'000'000;

// n events: M2M 40 + k ms, G2G 100 + 2k ms (k = 0..n-1) plus `shift` ms on both; the last event
// without its LED time (missing G2G and E2E).
analysis::FullLoopResult file(const std::string& name, int n, std::int64_t shift_ms) {
  formats::FullLoopImport rows;
  for (int k = 0; k < n; ++k) {
    formats::FullLoopRow r;
    r.line = k + 2;
    const std::int64_t t = kT0 + std::int64_t{k} * 2000 * kMs;
    const std::int64_t m2m = (40 + k + shift_ms) * kMs, g2g = (100 + 2 * k + shift_ms) * kMs;
    r.ns = {t + m2m, t + m2m + 600 * kMs, t + m2m + kMs, t, t + 550 * kMs, t + m2m + kMs + g2g};
    if (k == n - 1) r.ns[formats::kLedOn].reset();
    rows.rows.push_back(r);
  }
  stats::SummaryOptions options;
  options.thresholds = {core::Duration{150 * kMs}};
  return analysis::analyse_full_loop(name, name + ".csv", rows, options);
}

TEST(FullLoopView, RowsPerFileAndQuantityWithExclusions) {
  const std::vector<analysis::FullLoopResult> results{file("a", 5, 0)};
  const auto header = full_loop_header(results);
  EXPECT_EQ(header.back(), "> 150 ms");
  const auto rows = full_loop_rows(results);
  ASSERT_EQ(rows.size(), 5u);
  EXPECT_EQ(rows[0][0], "a");
  EXPECT_EQ(rows[0][1], "M2M");
  EXPECT_EQ(rows[0][3], "0 / 0 / 0");
  EXPECT_EQ(rows[0][4], "5");     // n
  EXPECT_EQ(rows[0][5], "42.0");  // median of 40..44 ms
  EXPECT_EQ(rows[1][1], "G2G");
  EXPECT_EQ(rows[1][3], "1 / 0 / 0");  // the missing LED time
  EXPECT_EQ(rows[2][1], "E2E");
  EXPECT_EQ(rows[2][4], "4");
  EXPECT_EQ(rows[3][1], "vehicle motion");
  EXPECT_EQ(rows[3][5], "600.0");
  const auto text = full_loop_table(results);
  EXPECT_NE(text.find("E2E = M2M + G2G"), std::string::npos);
}

TEST(FullLoopView, JsonAndCsvCarryEveryQuantity) {
  const std::vector<analysis::FullLoopResult> results{file("a", 5, 0)};
  const auto j = full_loop_json(results);
  ASSERT_EQ(j.size(), 1u);
  EXPECT_EQ(j[0]["format"], "full-loop-csv");
  EXPECT_EQ(j[0]["events"], 5);
  EXPECT_EQ(j[0]["quantities"]["g2g"]["excluded"]["missing"], 1);
  EXPECT_EQ(j[0]["quantities"]["e2e"]["summary"]["n"], 4);
  // E2E = 140, 143, 146, 149 ms: mean 144.5.
  EXPECT_DOUBLE_EQ(j[0]["quantities"]["e2e"]["summary"]["mean_ms"].get<double>(), 144.5);
  EXPECT_EQ(j[0]["quantities"]["e2e"]["summary"]["min"]["sample_id"], 2);  // the row's line
  const auto csv = full_loop_csv(results);
  std::istringstream in(csv);
  std::string line;
  std::getline(in, line);
  EXPECT_EQ(line.substr(0, 30), "scenario,file,quantity,events,");
  EXPECT_NE(line.find(",above_150ms_fraction"), std::string::npos);
  std::getline(in, line);
  EXPECT_EQ(line.substr(0, 17), "a,a.csv,m2m,5,5,0");
  int lines = 1;
  while (std::getline(in, line)) ++lines;
  EXPECT_EQ(lines, 5);
}

TEST(FullLoopView, TheFigureHasM2MG2GE2EPerFile) {
  formats::CameraLatencyImport camera{{45 * kMs, 47 * kMs, 50 * kMs}, {2, 3, 4}};
  const std::vector<analysis::FullLoopResult> results{
      file("a", 5, 0), analysis::analyse_camera_latency("cam", "cam.txt", camera, {})};
  const auto boxes = full_loop_boxes(results);
  ASSERT_EQ(boxes.size(), 4u);
  EXPECT_EQ(boxes[0].scenario, "M2M");
  EXPECT_EQ(boxes[0].group, "a");
  EXPECT_DOUBLE_EQ(boxes[0].median, 42.0);
  EXPECT_EQ(boxes[2].scenario, "E2E");
  EXPECT_DOUBLE_EQ(boxes[2].median, 144.5);
  EXPECT_EQ(boxes[3].scenario, "G2G");
  EXPECT_EQ(boxes[3].group, "cam");
  EXPECT_DOUBLE_EQ(boxes[3].median, 47.0);

  Report r;
  r.full_loops = results;
  const auto html = report_html(r);
  EXPECT_NE(html.find("data-chart=\"full-loop\""), std::string::npos);
  EXPECT_NE(html.find("data-table=\"full-loop\""), std::string::npos);
  // Only full-loop files: the matcher's empty sections are left out.
  EXPECT_EQ(html.find("data-chart=\"box\""), std::string::npos);
  EXPECT_EQ(html.find("data-table=\"scenarios\""), std::string::npos);
  EXPECT_NE(report_markdown(r).find("## Full loop"), std::string::npos);
  EXPECT_EQ(report_text(r).find("pairs"), std::string::npos);  // no empty table of scenarios

  m2mlat::testing::TempDir dir;
  const auto names = write_pgfplots(r, dir.path());
  EXPECT_NE(std::find(names.begin(), names.end(), "full-loop.tex"), names.end());
  EXPECT_EQ(std::find(names.begin(), names.end(), "box.tex"), names.end());
  std::ifstream dat(dir.path() / "full-loop.dat");
  std::stringstream all;
  all << dat.rdbuf();
  EXPECT_NE(all.str().find("a E2E 4 "), std::string::npos) << all.str();
  EXPECT_NE(all.str().find("cam G2G 3 "), std::string::npos) << all.str();
}

TEST(FullLoopView, TwoFilesCompareQuantityByQuantity) {
  Report r;
  r.full_loops = {file("a", 12, 0), file("b", 12, 5)};
  EXPECT_EQ(default_full_loop_comparisons(r), (std::vector<std::pair<std::string, std::string>>{{"b", "a"}}));
  stats::CompareOptions options;
  options.resamples = 0;
  const auto c = compare_full_loops(r, "b", "a", options);
  ASSERT_EQ(c.size(), 3u);
  EXPECT_EQ(c[0].subject, "b M2M");
  EXPECT_EQ(c[0].baseline, "a M2M");
  EXPECT_DOUBLE_EQ(c[0].comparison.median_difference_ms, 5.0);
  EXPECT_EQ(c[2].subject, "b E2E");
  EXPECT_DOUBLE_EQ(c[2].comparison.median_difference_ms, 10.0);
  EXPECT_THROW(compare_full_loops(r, "c", "a", options), core::Error);
}

}  // namespace
}  // namespace m2mlat::report::full_loop_view_test
