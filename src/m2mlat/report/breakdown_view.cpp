#include "m2mlat/report/breakdown_view.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "m2mlat/core/printable.hpp"
#include "m2mlat/formats/fields.hpp"
#include "m2mlat/report/pgfplots.hpp"
#include "m2mlat/report/svg_plot.hpp"
#include "m2mlat/report/table.hpp"

namespace m2mlat::report {

namespace {

double bd_ms(double ns) { return ns / 1e6; }
nlohmann::json bd_number(double v) { return std::isnan(v) ? nlohmann::json(nullptr) : nlohmann::json(v); }

// "network: 3 missing, 1 out_of_order" -> one text for the table.
std::string gap_text(const analysis::Breakdown& b) {
  std::string out;
  for (const auto& g : b.gaps)
    out += fmt::format("{}{} {} at {}", out.empty() ? "" : ", ", g.count, analysis::to_string(g.gap), g.stage);
  return out;
}

}  // namespace

BreakdownResults with_breakdown(std::span<const analysis::ScenarioResult> results) {
  BreakdownResults out;
  for (const auto& r : results)
    if (r.breakdown) out.push_back(&r);
  return out;
}

std::string breakdown_table(const BreakdownResults& results) {
  std::string out;
  for (const auto* r : results) {
    const auto& b = *r->breakdown;
    out += fmt::format("breakdown of {}: {} events, {} complete, {} incomplete{}{}\n",
                       core::printable(r->input.scenario), b.events.size(), b.complete, b.incomplete,
                       b.incomplete > 0 ? ": " : "", gap_text(b));
    Table t({"stage (ms)", "ends at", "median", "Q1", "Q3", "IQR", "mean", "share"});
    for (const auto& s : b.stages)
      t.add_row({s.name, s.selector, ms_text(bd_ms(s.median_ns), 3), ms_text(bd_ms(s.q1_ns), 3),
                 ms_text(bd_ms(s.q3_ns), 3), ms_text(bd_ms(s.q3_ns - s.q1_ns), 3), ms_text(bd_ms(s.mean_ns), 3),
                 percent_text(s.share)});
    t.add_row({"M2M", "", ms_text(bd_ms(b.m2m_median_ns), 3), "", "", "", ms_text(bd_ms(b.m2m_mean_ns), 3),
               b.complete > 0 ? "100.0 %" : "-"});
    out += t.render();
    out += "(over the complete events; share = the stage's sum / the M2M's sum, so the shares add up to 100 %)\n";
  }
  return out;
}

nlohmann::json breakdown_json(const analysis::Breakdown& b) {
  auto stages = nlohmann::json::array();
  for (const auto& s : b.stages)
    stages.push_back({{"name", s.name},
                      {"ends_at", s.selector},
                      {"median_ms", bd_number(bd_ms(s.median_ns))},
                      {"q1_ms", bd_number(bd_ms(s.q1_ns))},
                      {"q3_ms", bd_number(bd_ms(s.q3_ns))},
                      {"iqr_ms", bd_number(bd_ms(s.q3_ns - s.q1_ns))},
                      {"mean_ms", bd_number(bd_ms(s.mean_ns))},
                      {"min_ns", b.complete > 0 ? nlohmann::json(s.min_ns) : nlohmann::json(nullptr)},
                      {"max_ns", b.complete > 0 ? nlohmann::json(s.max_ns) : nlohmann::json(nullptr)},
                      {"share", bd_number(s.share)}});
  auto gaps = nlohmann::json::array();
  for (const auto& g : b.gaps)
    gaps.push_back({{"stage", g.stage}, {"reason", analysis::to_string(g.gap)}, {"count", g.count}});
  return {{"events", b.complete + b.incomplete},  // = events.size(); the live view keeps no rows
          {"complete", b.complete},
          {"incomplete", b.incomplete},
          {"m2m_median_ms", bd_number(bd_ms(b.m2m_median_ns))},
          {"m2m_mean_ms", bd_number(bd_ms(b.m2m_mean_ns))},
          {"stages", std::move(stages)},
          {"incomplete_by_reason", std::move(gaps)}};
}

std::string breakdown_csv(const BreakdownResults& scenarios) {
  // The header first, no comment line (as every CSV m2mlat writes for other tools: docs/formats.md).
  std::string out = "scenario,pair,cause_id,cause_ns,effect_ns,m2m_ns,status,gap_stage,detail,stage,stage_ns\n";
  for (const auto* r : scenarios) {
    const auto& b = *r->breakdown;
    for (const auto& e : b.events) {
      // One row per stage measured (the stages before the gap for an incomplete chain; one row with
      // an empty stage when the first is missing), so a spreadsheet's pivot gives the table.
      const std::size_t rows = std::max<std::size_t>(1, e.stage_ns.size());
      for (std::size_t k = 0; k < rows; ++k) {
        formats::append_csv_field(out, r->input.scenario);
        out += fmt::format(",{},{},{},{},{},{},", e.pair, e.cause_id, e.cause_time.ns(), e.effect_time.ns(), e.m2m_ns,
                           e.complete() ? "complete" : analysis::to_string(e.gap));
        if (!e.complete()) formats::append_csv_field(out, b.stages[e.gap_stage].name);
        out += ',';
        formats::append_csv_field(out, e.detail);
        out += ',';
        if (k < e.stage_ns.size()) {
          formats::append_csv_field(out, b.stages[k].name);
          out += fmt::format(",{}", e.stage_ns[k]);
        } else {
          out += ',';
        }
        out += '\n';
      }
    }
  }
  return out;
}

std::string breakdown_svg(const BreakdownResults& scenarios) {
  if (scenarios.empty()) return {};
  double top = 0;
  for (const auto* r : scenarios)
    if (!std::isnan(r->breakdown->m2m_mean_ns)) top = std::max(top, bd_ms(r->breakdown->m2m_mean_ns));
  if (top <= 0) top = 1;
  const double n = static_cast<double>(scenarios.size());
  SvgPlot plot("breakdown", "Where the time goes: mean of each stage", "scenario", "time (ms)", -0.5, n - 0.5, 0,
               top * 1.08);
  std::vector<std::pair<double, std::string>> categories;
  const auto& first = scenarios.front()->breakdown->stages;
  for (std::size_t i = 0; i < scenarios.size(); ++i) {
    const auto& b = *scenarios[i]->breakdown;
    const double x = static_cast<double>(i);
    categories.emplace_back(x, fmt::format("{} (n {})", scenarios[i]->input.scenario, b.complete));
    double base = 0;
    for (std::size_t k = 0; k < b.stages.size(); ++k) {
      const double h = bd_ms(b.stages[k].mean_ns);
      if (std::isnan(h)) continue;
      plot.rect(x - 0.3, base, x + 0.3, base + h, palette(k));
      base += h;
    }
  }
  plot.set_x_categories(std::move(categories));
  std::vector<std::pair<std::string, std::string>> legend;
  for (std::size_t k = 0; k < first.size(); ++k) legend.emplace_back(first[k].name, std::string(palette(k)));
  plot.legend(legend);
  plot.note("stacked means add up to the mean M2M of the complete events (ms)");
  return plot.render();
}

std::vector<std::pair<std::string, std::string>> breakdown_pgfplots(const BreakdownResults& scenarios) {
  if (scenarios.empty()) return {};
  const auto& first = scenarios.front()->breakdown->stages;
  // breakdown.dat: one row per scenario (its position, n), one column of mean ms per stage.
  std::string dat = "x n";
  for (std::size_t k = 0; k < first.size(); ++k) dat += fmt::format(" s{}", k);
  dat += '\n';
  std::string ticks, labels;
  for (std::size_t i = 0; i < scenarios.size(); ++i) {
    const auto& b = *scenarios[i]->breakdown;
    dat += fmt::format("{} {}", i, b.complete);
    for (const auto& s : b.stages)
      dat += std::isnan(s.mean_ns) ? std::string(" 0") : fmt::format(" {:.6f}", bd_ms(s.mean_ns));
    dat += '\n';
    ticks += fmt::format("{}{}", i == 0 ? "" : ",", i);
    labels += fmt::format("{}{{{}}}", i == 0 ? "" : ",", tex_escape(scenarios[i]->input.scenario));
  }
  std::string tex = fmt::format(
      "% Where the time goes: the mean of each stage per scenario, stacked (ms) -- written by m2mlat report.\n"
      "\\providecommand\\mtwomlatdir{{}}%\n"
      "\\begin{{tikzpicture}}\n\\begin{{axis}}[ybar stacked, bar width=0.5, width=0.95\\linewidth, height=6cm,\n"
      "  ymin=0, ylabel={{time (ms)}}, xtick={{{}}}, xticklabels={{{}}}, enlarge x limits=0.3,\n"
      "  legend style={{at={{(1.02,1)}}, anchor=north west}}, legend cell align=left,\n"
      "  title={{Mean of each stage (adds up to the mean M2M)}}]\n",
      ticks, labels);
  static constexpr const char* kBarColours[] = {"blue!70!black", "orange!90!black", "green!50!black",
                                                "red!75!black",  "violet",          "cyan!70!black",
                                                "olive",         "black"};
  for (std::size_t k = 0; k < first.size(); ++k)
    tex += fmt::format(
        "\\addplot[fill={0}, draw=black] table[x=x, y=s{1}] {{\\mtwomlatdir breakdown.dat}};\n"
        "\\addlegendentry{{{2}}}\n",
        kBarColours[k % 8], k, tex_escape(first[k].name));
  tex += "\\end{axis}\n\\end{tikzpicture}\n";
  return {{"breakdown.tex", tex}, {"breakdown.dat", dat}};
}

}  // namespace m2mlat::report
