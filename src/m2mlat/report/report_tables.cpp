// Text, Markdown and CSV views of a report. CSV numbers: ms with 6 decimals (exact to the ns),
// ratios and p values with 6 significant digits; an undefined value is an empty field.
#include "m2mlat/report/report_tables.hpp"

#include <fmt/format.h>

#include <cmath>

#include "m2mlat/core/printable.hpp"
#include "m2mlat/report/breakdown_view.hpp"
#include "m2mlat/report/comparison_text.hpp"
#include "m2mlat/report/full_loop_view.hpp"
#include "m2mlat/report/resampling_text.hpp"
#include "m2mlat/report/scenario_text.hpp"
#include "m2mlat/report/table.hpp"

namespace m2mlat::report {

namespace {
std::string f6(double x) { return std::isnan(x) ? "" : fmt::format("{:.6f}", x); }
std::string g6(double x) { return std::isnan(x) ? "" : fmt::format("{:.6g}", x); }
std::string opt6(const std::optional<double>& x) { return x ? f6(*x) : ""; }

std::string csv_field(const std::string& s) {
  if (s.find_first_of(",\"\n") == std::string::npos) return s;
  std::string out = "\"";
  for (char ch : s) out += ch == '"' ? std::string("\"\"") : std::string(1, ch);
  return out + "\"";
}

// A threshold as a column name's part: "170ms", "2500000ns".
std::string threshold_column(core::Duration t) {
  const auto ns = t.count();
  if (ns % 1'000'000 == 0) return fmt::format("{}ms", ns / 1'000'000);
  return fmt::format("{}ns", ns);
}

std::vector<analysis::ScenarioResult> results_of(const Report& r) {
  std::vector<analysis::ScenarioResult> out;
  for (const auto& s : r.scenarios) out.push_back(s.result);
  return out;
}

std::string md_cell(double x, int decimals = 1) {
  return std::isnan(x) ? "–" : fmt::format("{:.{}f}", x, decimals);
}
// Markdown-escaped and printable (the report is read on a terminal too: core/printable.hpp).
std::string md_escape(const std::string& s) {
  std::string out;
  for (char ch : core::printable(s)) {
    if (ch == '|' || ch == '_' || ch == '*' || ch == '\\') out += '\\';
    out += ch;
  }
  return out;
}
}  // namespace

std::string report_text(const Report& report) {
  const auto results = results_of(report);
  std::string out;
  if (!report.scenarios.empty() || report.full_loops.empty())
    out = pairing_table(results) + "\n" + scenario_table(results);
  if (const auto flagged = flagged_effect_table(results); !flagged.empty()) out += "\n" + flagged;
  if (!report.full_loops.empty()) out += (out.empty() ? "" : "\n") + full_loop_table(report.full_loops);
  if (const auto steps = clock_step_table(results); !steps.empty()) out += "\n" + steps;
  {
    BreakdownResults breakdowns;
    for (const auto& s : report.scenarios)
      if (s.result.breakdown) breakdowns.push_back(&s.result);
    if (!breakdowns.empty()) out += "\n" + breakdown_table(breakdowns);
  }
  bool any_uncertainty = false;
  for (const auto& s : report.scenarios) any_uncertainty |= s.median_uncertainty_ms().has_value();
  if (any_uncertainty) {
    Table t({"scenario", "group", "pairs with bound", "median U95 (ms)", "max U95 (ms)", "median bound (ms)",
             "cause clock", "effect clock"});
    for (const auto& s : report.scenarios) {
      std::size_t known = 0;
      for (const auto& u : s.uncertainty_ns) known += u ? 1 : 0;
      const auto ms = [](const std::optional<double>& x) { return x ? fmt::format("{:.3f}", *x) : "-"; };
      t.add_row({s.result.input.scenario, s.group.empty() ? "-" : s.group, std::to_string(known),
                 ms(s.median_uncertainty_ms()), ms(s.max_uncertainty_ms()), ms(s.median_bound_ms()),
                 ms(s.result.cause_clock_ms), ms(s.result.effect_clock_ms)});
    }
    out +=
        "\nmeasurement uncertainty per latency (U95: expanded uncertainty, k = 2; bound: worst case, both "
        "boards' clock bounds + --kernel-error; cause/effect clock: each board's median bound)\n" +
        t.render();
  }
  if (!report.comparisons.empty()) {
    out += "\ncomparisons (subject - baseline; ratios subject / baseline)\n" +
           comparison_table(report.comparisons);
    out += "\n";
    for (const auto& c : report.comparisons) out += comparison_sentence(c) + "\n";
  }
  return out;
}

std::string report_markdown(const Report& report) {
  std::string out = "# Latency report\n\n";
  out +=
      "| scenario | group | pairs | median (ms) | IQR (ms) | mean (ms) | SD (ms) | min (ms) | max (ms) | P95 "
      "(ms)";
  const auto& first = report.scenarios.empty() ? nullptr : &report.scenarios.front().result.summary;
  if (first)
    for (const auto& t : first->thresholds) out += fmt::format(" | > {}", threshold_column(t.threshold));
  out += " |\n|---|---|---:|---:|---:|---:|---:|---:|---:|---:";
  if (first)
    for (std::size_t k = 0; k < first->thresholds.size(); ++k) out += "|---:";
  out += "|\n";
  for (const auto& s : report.scenarios) {
    const auto& m = s.result.summary;
    out +=
        fmt::format("| {} | {} | {} | {} | {} | {} | {} | {} | {} | {}", md_escape(s.result.input.scenario),
                    md_escape(s.group), m.n, md_cell(m.median_ms), md_cell(m.iqr_ms), md_cell(m.mean_ms),
                    md_cell(m.sd_ms), m.min ? md_cell(m.min->ms()) : "–", m.max ? md_cell(m.max->ms()) : "–",
                    md_cell(m.p95_ms));
    for (const auto& t : m.thresholds) out += fmt::format(" | {} %", md_cell(t.fraction_above * 100));
    out += " |\n";
  }
  std::vector<std::vector<std::string>> flagged;
  for (const auto& s : report.scenarios)
    if (auto row = flagged_effect_row(s.result); !row.empty()) flagged.push_back(std::move(row));
  if (!flagged.empty()) {
    out += "\n## What the flagged pairs do\n\nMedian and IQR in ms, without and with the pairs the matcher "
           "flagged; \"in statistics\": the table above holds them (`--include-ambiguous`).\n\n|";
    const auto header = flagged_effect_header();
    for (const auto& h : header) out += " " + md_escape(h) + " |";
    out += "\n|---|---:|---|---:|---:|---:|---:|---|\n";
    for (const auto& row : flagged) {
      out += "|";
      for (const auto& cell : row) out += " " + md_escape(cell) + " |";
      out += "\n";
    }
  }
  if (!report.full_loops.empty()) {
    // M2M, G2G, E2E and the motion durations of the full-loop files (report/full_loop_view.hpp).
    const auto header = full_loop_header(report.full_loops);
    out += "\n## Full loop\n\n|";
    for (const auto& h : header) out += " " + md_escape(h) + " |";
    out += "\n|";
    for (std::size_t k = 0; k < header.size(); ++k) out += k < 2 ? "---|" : "---:|";
    out += "\n";
    for (auto& row : full_loop_rows(report.full_loops)) {
      row.resize(header.size(), "–");
      out += "|";
      for (const auto& cell : row) out += " " + md_escape(cell) + " |";
      out += "\n";
    }
  }
  if (!report.comparisons.empty()) {
    out += "\n## Comparisons\n\n";
    out +=
        "| subject vs baseline | median diff (ms) | CI | Mann-Whitney p | IQR ratio | CI | SD ratio | CI | "
        "Brown-Forsythe p |\n|---|---:|---|---:|---:|---|---:|---|---:|\n";
    const auto ci = [](const stats::Interval& i, int d) {
      return std::isnan(i.lower) ? std::string("–")
                                 : fmt::format("{:.{}f} to {:.{}f}", i.lower, d, i.upper, d);
    };
    for (const auto& r : report.comparisons) {
      const auto& c = r.comparison;
      out += fmt::format("| {} vs {} | {:+.1f} | {} | {} | {:.3f} | {} | {:.3f} | {} | {} |\n",
                         md_escape(r.subject), md_escape(r.baseline), c.median_difference_ms,
                         ci(c.median_difference_ci_ms, 1), fmt::format("{:.2g}", c.mann_whitney.p),
                         c.iqr_ratio, ci(c.iqr_ratio_ci, 3), c.sd_ratio, ci(c.sd_ratio_ci, 3),
                         fmt::format("{:.2g}", c.brown_forsythe.p));
    }
    out += "\n";
    for (const auto& r : report.comparisons) out += "- " + md_escape(comparison_sentence(r)) + "\n";
  }
  out += fmt::format("\nProduced by `{}`", core::printable(report.command));
  for (const auto& [name, version] : report.versions) out += fmt::format(", {} {}", name, version);
  out += ".\n";
  return out;
}

std::string scenarios_csv(const Report& report) {
  std::string out =
      "scenario,group,n,pairs,ambiguous_pairs,median_ms,q1_ms,q3_ms,iqr_ms,mean_ms,sd_ms,min_ms,max_ms,p5_ms,"
      "p90_ms,"
      "p95_ms,p99_ms,median_ci_low_ms,median_ci_high_ms,iqr_ci_low_ms,iqr_ci_high_ms,ci_resampled,"
      "uncertainty_median_ms";
  const auto* first = report.scenarios.empty() ? nullptr : &report.scenarios.front().result.summary;
  if (first)
    for (const auto& t : first->thresholds)
      out += fmt::format(",above_{}_fraction", threshold_column(t.threshold));
  out += "\n";
  for (const auto& s : report.scenarios) {
    const auto& m = s.result.summary;
    out += fmt::format("{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{}",
                       csv_field(s.result.input.scenario), csv_field(s.group), m.n,
                       s.result.match.pairs.size(), s.result.ambiguous_pairs(), f6(m.median_ms), f6(m.q1_ms),
                       f6(m.q3_ms), f6(m.iqr_ms), f6(m.mean_ms), f6(m.sd_ms), m.min ? f6(m.min->ms()) : "",
                       m.max ? f6(m.max->ms()) : "", f6(m.p5_ms), f6(m.p90_ms), f6(m.p95_ms), f6(m.p99_ms));
    if (m.bootstrap)
      out += fmt::format(",{},{},{},{},{}", f6(m.bootstrap->median_ms.lower), f6(m.bootstrap->median_ms.upper),
                         f6(m.bootstrap->iqr_ms.lower), f6(m.bootstrap->iqr_ms.upper),
                         csv_field(resampling_name(m.bootstrap->resampling)));
    else
      out += ",,,,,";
    out += "," + opt6(s.median_uncertainty_ms());
    for (const auto& t : m.thresholds) out += "," + g6(t.fraction_above);
    out += "\n";
  }
  return out;
}

std::string comparisons_csv(const Report& report) {
  std::string out =
      "subject,baseline,n_subject,n_baseline,median_subject_ms,median_baseline_ms,median_difference_ms,"
      "median_difference_ci_low_ms,median_difference_ci_high_ms,mann_whitney_u,mann_whitney_p,iqr_subject_ms,"
      "iqr_baseline_ms,iqr_ratio,iqr_ratio_ci_low,iqr_ratio_ci_high,sd_ratio,sd_ratio_ci_low,sd_ratio_ci_"
      "high,"
      "brown_forsythe_w,brown_forsythe_p,uncertainty_ms,median_difference_below_uncertainty";
  const auto* first = report.comparisons.empty() ? nullptr : &report.comparisons.front().comparison;
  if (first)
    for (const auto& d : first->shares) {
      const auto t = threshold_column(d.threshold);
      out += fmt::format(
          ",above_{0}_subject,above_{0}_baseline,above_{0}_difference,above_{0}_ci_low,above_{0}_ci_high", t);
    }
  out += "\n";
  for (const auto& r : report.comparisons) {
    const auto& c = r.comparison;
    out += fmt::format(
        "{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{}", csv_field(r.subject),
        csv_field(r.baseline), c.n_subject, c.n_baseline, f6(c.median_subject_ms), f6(c.median_baseline_ms),
        f6(c.median_difference_ms), f6(c.median_difference_ci_ms.lower), f6(c.median_difference_ci_ms.upper),
        g6(c.mann_whitney.u_a), g6(c.mann_whitney.p), f6(c.iqr_subject_ms), f6(c.iqr_baseline_ms),
        g6(c.iqr_ratio), g6(c.iqr_ratio_ci.lower), g6(c.iqr_ratio_ci.upper), g6(c.sd_ratio),
        g6(c.sd_ratio_ci.lower), g6(c.sd_ratio_ci.upper), g6(c.brown_forsythe.w), g6(c.brown_forsythe.p),
        opt6(c.uncertainty_ms),
        c.uncertainty_ms ? (c.median_difference_below_uncertainty ? "true" : "false") : "");
    for (const auto& d : c.shares)
      out += fmt::format(",{},{},{},{},{}", g6(d.share_subject), g6(d.share_baseline), g6(d.difference),
                         g6(d.ci.lower), g6(d.ci.upper));
    out += "\n";
  }
  return out;
}

std::string full_loop_csv(std::span<const analysis::FullLoopResult> results) {
  std::string out =
      "scenario,file,quantity,events,n,excluded_missing,excluded_impossible,excluded_overflow,mean_ms,sd_ms,"
      "min_ms,p5_ms,q1_ms,median_ms,q3_ms,p90_ms,p95_ms,p99_ms,iqr_ms,max_ms";
  const auto* limits = full_loop_thresholds(results);
  if (limits)
    for (const auto& share : *limits) out += fmt::format(",above_{}_fraction", threshold_column(share.threshold));
  out += "\n";
  for (const auto& r : results)
    for (const auto q : analysis::kLoopQuantities) {
      const auto* s = r.find(q);
      if (s == nullptr) continue;
      const auto& m = s->summary;
      out += fmt::format("{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{}", csv_field(r.scenario),
                         csv_field(r.file), analysis::key(q), r.events, m.n, s->excluded[0], s->excluded[1],
                         s->excluded[2], f6(m.mean_ms), f6(m.sd_ms), m.min ? f6(m.min->ms()) : "",
                         f6(m.p5_ms), f6(m.q1_ms), f6(m.median_ms), f6(m.q3_ms), f6(m.p90_ms), f6(m.p95_ms),
                         f6(m.p99_ms), f6(m.iqr_ms), m.max ? f6(m.max->ms()) : "");
      for (const auto& share : m.thresholds) out += "," + g6(share.fraction_above);
      // A motion has no shares above the latency limits: its cells are empty.
      for (std::size_t k = m.thresholds.size(); limits && k < limits->size(); ++k) out += ",";
      out += "\n";
    }
  return out;
}

}  // namespace m2mlat::report
