// The report writers: golden files for CSV, JSON and Markdown (tests/data/report/; regenerate with
// M2MLAT_UPDATE_GOLDEN=1 after a deliberate change and review the diff), and the pieces behind the
// HTML and pgfplots output: groups, default comparisons, per-pair uncertainty, thinning of figures.
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "m2mlat/analysis/scenario_result.hpp"
#include "m2mlat/core/error.hpp"
#include "m2mlat/report/comparison_text.hpp"
#include "m2mlat/report/html_report.hpp"
#include "m2mlat/report/pgfplots.hpp"
#include "m2mlat/report/plot_data.hpp"
#include "m2mlat/report/report_json.hpp"
#include "m2mlat/report/report_tables.hpp"
#include "m2mlat/report/svg_plot.hpp"
#include "temp_dir.hpp"

namespace m2mlat::report {
namespace {

using namespace std::chrono_literals;

// A scenario of n manoeuvres 4 s apart whose latency is base + a fixed pattern of spread (ms).
analysis::ScenarioResult scenario(const std::string& name, std::int64_t base_ms, std::int64_t spread_ms,
                                  int n) {
  analysis::ScenarioInput in;
  in.scenario = name;
  in.cause_ref = {"operator", "wheel"};
  in.effect_ref = {"vehicle", "wheel"};
  in.id_kind = "index";
  for (int i = 0; i < n; ++i) {
    const std::int64_t t = 1'700'000'000'000'000'000 + std::int64_t{i} * 4'000'000'000;
    const std::int64_t latency_ms =
        base_ms + ((i * 37) % 17 - 8) * spread_ms / 8 + (i % 5 == 0 ? spread_ms : 0);
    in.cause.seq.push_back(i);
    in.cause.t_ns.push_back(t);
    in.effect.seq.push_back(i);
    in.effect.t_ns.push_back(t + latency_ms * 1'000'000 + i * 1013);
  }
  stats::SummaryOptions so;
  so.bootstrap = stats::BootstrapOptions{200, 1, 0.95};
  return analysis::analyse(std::move(in), {}, so);
}

Report sample_report() {
  Report r;
  r.command = "m2mlat report golden.db";
  r.versions = {{"m2mlat", "test"}};
  for (auto res : {scenario("static_wifi", 870, 100, 40), scenario("static_5g", 930, 50, 36),
                   scenario("dynamic_co", 770, 70, 30), scenario("dynamic_auto", 815, 75, 30)}) {
    r.scenarios.push_back(scenario_report(std::move(res)));
  }
  // Clock data for the first scenario: both boards with a constant 0.2 ms and 0.3 ms bound.
  auto& first = r.scenarios.front();
  for (const char* node : {"operator", "vehicle"}) {
    analysis::ClockSeries c{node, "sim", {}, {}, {}};
    for (int k = 0; k < 20; ++k) {
      c.t_ns.push_back(1'700'000'000'000'000'000 + std::int64_t{k} * 10'000'000'000);
      c.offset_ns.push_back(k * 1000);
      c.max_error_ns.push_back(node[0] == 'o' ? 200'000 : 300'000);
    }
    first.result.clocks.push_back(c);
  }
  for (std::size_t i = 0; i < first.result.match.pairs.size(); ++i) {
    first.uncertainty_ns[i] = 500'000;
    first.max_error_ns[i] = 2'000'000;
  }
  first.result.cause_clock_ms = 0.2;
  first.result.effect_clock_ms = 0.3;
  first.result.losses.push_back({"vehicle", "seqno_gap", 1, 3});
  r.assumed_uncertainty_ms = 1.0;
  assign_groups(r, {}, true);
  stats::CompareOptions o;
  o.resamples = 200;
  o.thresholds = {1s};
  for (const auto& [s, b] : default_comparisons(r)) r.comparisons.push_back(compare_scenarios(r, s, b, o));
  return r;
}

void check_golden(const std::string& name, const std::string& text) {
  const auto path = std::filesystem::path(M2MLAT_TEST_DATA) / "report" / name;
  if (std::getenv("M2MLAT_UPDATE_GOLDEN")) {
    std::ofstream(path, std::ios::binary) << text;
    GTEST_SKIP() << "rewrote " << path;
  }
  std::ifstream in(path, std::ios::binary);
  ASSERT_TRUE(in) << "missing golden file " << path << " (run with M2MLAT_UPDATE_GOLDEN=1)";
  std::stringstream want;
  want << in.rdbuf();
  EXPECT_EQ(text, want.str()) << "differs from " << path;
}

TEST(ReportGolden, Csv) {
  const auto r = sample_report();
  check_golden("scenarios.csv", scenarios_csv(r));
  check_golden("comparisons.csv", comparisons_csv(r));
}
TEST(ReportGolden, Json) { check_golden("report.json", report_document(sample_report()).dump(2) + "\n"); }
TEST(ReportGolden, Markdown) { check_golden("report.md", report_markdown(sample_report())); }

TEST(ReportModel, GroupsByPrefixAndComparesWithinGroups) {
  const auto r = sample_report();
  EXPECT_EQ(r.groups, (std::vector<std::string>{"static", "dynamic"}));
  ASSERT_EQ(r.comparisons.size(), 2u);
  EXPECT_EQ(r.comparisons[0].subject, "static_5g");
  EXPECT_EQ(r.comparisons[0].baseline, "static_wifi");
  // The first scenario's clock data (0.5 ms per pair) sets the uncertainty of its comparison; the
  // other comparison uses the assumed 1 ms.
  EXPECT_EQ(r.comparisons[0].comparison.uncertainty_ms, 0.5);
  EXPECT_EQ(r.comparisons[1].comparison.uncertainty_ms, 1.0);
}

TEST(ReportModel, ExplicitGroupsAndErrors) {
  auto r = sample_report();
  assign_groups(r, {{"fast", {"static_5g", "dynamic_co"}}}, true);
  EXPECT_EQ(r.groups, (std::vector<std::string>{"fast", "other"}));
  EXPECT_EQ(r.scenarios[1].group, "fast");
  EXPECT_EQ(r.scenarios[0].group, "other");
  EXPECT_THROW(assign_groups(r, {{"x", {"nope"}}}, true), core::Error);
  EXPECT_THROW(compare_scenarios(r, "nope", "static_5g", {}), core::Error);
  assign_groups(r, {}, false);
  EXPECT_TRUE(r.groups.empty());
  EXPECT_EQ(default_comparisons(r).size(), 6u);  // all pairs of 4
}

// The report draws the analysis' per-sample bound (analysis/uncertainty.hpp) and computes none: a
// bounded sample keeps its max_error, an unbounded or unknown one has none, and a result without
// clock samples has none at all.
TEST(ReportModel, PerPairUncertaintyAndBoundAreTheAnalysis) {
  auto res = scenario("bounded", 800, 50, 3);
  ASSERT_EQ(res.match.pairs.size(), 3u);
  analysis::SampleUncertainty bounded;
  bounded.max_error_ns = 4'200'000;
  bounded.u_ns = 210'000;
  analysis::SampleUncertainty unsynchronised;
  unsynchronised.flags = analysis::kUncertaintyUnsynchronised;
  unsynchronised.max_error_ns = analysis::kUnbounded;
  analysis::SampleUncertainty unknown;
  unknown.flags = analysis::kUncertaintyNoClock;
  res.uncertainty = {bounded, unsynchronised, unknown};
  const auto s = scenario_report(res);
  // Drawn and compared: the expanded uncertainty U95 = 2 u; the worst-case bound beside it.
  ASSERT_EQ(s.uncertainty_ns.size(), 3u);
  EXPECT_EQ(s.uncertainty_ns[0], 420'000);
  EXPECT_FALSE(s.uncertainty_ns[1].has_value());
  EXPECT_FALSE(s.uncertainty_ns[2].has_value());
  EXPECT_EQ(s.median_uncertainty_ms(), 0.42);
  ASSERT_EQ(s.max_error_ns.size(), 3u);
  EXPECT_EQ(s.max_error_ns[0], 4'200'000);
  EXPECT_FALSE(s.max_error_ns[1].has_value());
  EXPECT_EQ(s.median_bound_ms(), 4.2);
  res.uncertainty.clear();
  const auto none = scenario_report(res);
  EXPECT_EQ(none.uncertainty_ns, (std::vector<std::optional<std::int64_t>>(3)));
  EXPECT_FALSE(none.median_uncertainty_ms().has_value());
  EXPECT_FALSE(none.median_bound_ms().has_value());
}

TEST(ComparisonText, SentenceSaysNarrowerAndNotesUncertainty) {
  const auto r = sample_report();
  const auto s = comparison_sentence(r.comparisons[0]);
  EXPECT_NE(s.find("static_5g vs static_wifi: IQR "), std::string::npos) << s;
  EXPECT_NE(s.find("% narrower (95 % CI"), std::string::npos) << s;
  EXPECT_NE(s.find("(Mann-Whitney, significant)"), std::string::npos) << s;
  EXPECT_EQ(p_text(0.00001), "p < 0.0001");
  EXPECT_EQ(p_text(0.0123), "p = 0.012");
  ComparisonReport tiny = r.comparisons[0];
  tiny.comparison.uncertainty_ms = 1000.0;
  tiny.comparison.median_difference_below_uncertainty = true;
  EXPECT_NE(comparison_sentence(tiny).find("smaller than the measurement uncertainty"), std::string::npos);
}

TEST(PlotData, StatisticsOverAllSamplesSeriesThinned) {
  auto big = scenario("big_one", 800, 80, 5000);
  ScenarioReport s{std::move(big), {}, {}, {}};
  const auto box = box_data(s);
  EXPECT_DOUBLE_EQ(box.median, s.result.summary.median_ms);
  EXPECT_DOUBLE_EQ(box.q1, s.result.summary.q1_ms);
  const auto ts = time_series(s);
  EXPECT_TRUE(ts.binned);
  EXPECT_LE(ts.t_s.size(), kSeriesPoints);
  EXPECT_EQ(ts.samples, 5000u);
  const auto e = ecdf_data(s);
  EXPECT_LE(e.x.size(), kEcdfPoints);
  EXPECT_EQ(e.y.back(), 1.0);
  Report r;
  r.scenarios.push_back(std::move(s));
  const auto h = histogram_data(r, 10);
  std::size_t total = 0;
  for (auto c : h.counts[0]) total += c;
  EXPECT_EQ(total, 5000u);
}

TEST(Svg, TicksAndEscaping) {
  EXPECT_EQ(nice_ticks(0, 10, 5), (std::vector<double>{0, 2, 4, 6, 8, 10}));
  EXPECT_EQ(tick_label(0.25, 0.05), "0.25");
  EXPECT_EQ(xml_escape("a<b&\"c\""), "a&lt;b&amp;&quot;c&quot;");
  EXPECT_EQ(tex_escape("static_5g 50%"), "static\\_5g 50\\%");
}

// Category labels never overlap: too wide for their slot they alternate on two rows, too wide for two
// slots they are cut with an ellipsis and keep their whole name in a tooltip.
TEST(Svg, CategoryLabelsDoNotOverlap) {
  const auto labels = [](const std::vector<std::string>& names) {
    SvgPlot plot("c", "t", "x", "y", 0.5, static_cast<double>(names.size()) + 0.5, 0, 1, 400, 200);
    std::vector<std::pair<double, std::string>> cats;
    for (std::size_t k = 0; k < names.size(); ++k) cats.emplace_back(static_cast<double>(k) + 1, names[k]);
    plot.set_x_categories(std::move(cats));
    return plot.render();
  };
  const auto short_names = labels({"a", "b", "c"});
  EXPECT_NE(short_names.find(">b</text>"), std::string::npos);
  EXPECT_EQ(short_names.find("y=\"179\""), std::string::npos);  // one row: 200 - 48 + 14 = 166 only
  const auto wide = labels({"dynamic_co_referenced", "dynamic_autonomous", "static_5g_with_stalls"});
  EXPECT_NE(wide.find("y=\"179\""), std::string::npos);  // the second label on the second row
  const auto too_wide = labels({std::string(60, 'a') + "_end", "b", "c"});
  EXPECT_NE(too_wide.find("<title>" + std::string(60, 'a') + "_end</title>"), std::string::npos);
  EXPECT_EQ(too_wide.find("_end</text>"), std::string::npos);  // the shown text is cut
}

TEST(Html, SelfContainedWithEveryChart) {
  const auto html = report_html(sample_report());
  for (const char* chart :
       {"data-chart=\"box\"", "data-chart=\"ecdf\"", "data-chart=\"histogram\"",
        "data-chart=\"timeseries-0\"", "data-chart=\"timeseries-3\"", "data-chart=\"clock-0\"",
        "data-chart=\"budget\"", "data-table=\"losses\"", "data-table=\"comparisons\"", "data-chart=\"forest\""})
    EXPECT_NE(html.find(chart), std::string::npos) << chart;
  EXPECT_EQ(html.find("http://"), html.find("http://www.w3.org/2000/svg"));  // only the SVG namespace
  EXPECT_EQ(html.find("https://"), std::string::npos);
  EXPECT_EQ(html.find("<script"), std::string::npos);
  EXPECT_NE(html.find("m2mlat report golden.db"), std::string::npos);
}

TEST(Pgfplots, WritesFiguresAndData) {
  const m2mlat::testing::TempDir temp;
  const auto dir = temp.path() / "figures";  // made by write_pgfplots
  const auto files = write_pgfplots(sample_report(), dir);
  for (const char* f : {"box.tex", "box.dat", "ecdf.tex", "histogram.tex", "histogram.dat", "figures.tex", "forest.tex",
                        "forest.dat",
                        "timeseries-static_wifi.tex", "timeseries-static_wifi.dat", "clock-static_wifi.tex"})
    EXPECT_TRUE(std::filesystem::exists(dir / f)) << f;
  std::ifstream box(dir / "box.tex");
  std::stringstream text;
  text << box.rdbuf();
  EXPECT_NE(text.str().find("boxplot prepared"), std::string::npos);
  EXPECT_NE(text.str().find("\\draw[dashed, gray]"), std::string::npos);  // the latency limits
  std::ifstream histogram(dir / "histogram.tex");
  std::stringstream h;
  h << histogram.rdbuf();
  EXPECT_NE(h.str().find("x tick label as interval=false, xtick={"), std::string::npos);  // round ticks only
}

// A link planted in the figures folder under a figure's name is not written through.
TEST(Pgfplots, PlantedSymlinkRefused) {
  const m2mlat::testing::TempDir temp;
  const auto& dir = temp.path();
  std::ofstream(dir / "victim") << "precious\n";
  std::filesystem::create_symlink(dir / "victim", dir / "box.tex");
  try {
    write_pgfplots(sample_report(), dir);
    ADD_FAILURE() << "written through box.tex";
  } catch (const core::Error& e) {
    EXPECT_NE(std::string(e.what()).find((dir / "box.tex").string()), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("a symbolic link"), std::string::npos) << e.what();
  }
  std::ifstream victim(dir / "victim");
  std::stringstream text;
  text << victim.rdbuf();
  EXPECT_EQ(text.str(), "precious\n");
  EXPECT_TRUE(std::filesystem::is_symlink(dir / "box.tex"));
}

}  // namespace
}  // namespace m2mlat::report
