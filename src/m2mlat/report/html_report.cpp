// HTML page assembly and the charts, drawn with svg_plot from plot_data.
#include "m2mlat/report/html_report.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "m2mlat/analysis/pairing_counts.hpp"
#include "m2mlat/report/breakdown_view.hpp"
#include "m2mlat/report/comparison_text.hpp"
#include "m2mlat/report/full_loop_view.hpp"
#include "m2mlat/report/plot_data.hpp"
#include "m2mlat/report/resampling_text.hpp"
#include "m2mlat/report/scenario_text.hpp"
#include "m2mlat/report/svg_plot.hpp"
#include "m2mlat/report/table.hpp"

namespace m2mlat::report {

namespace {

constexpr const char* kCss = R"(
:root{--fg:#1b1b1b;--muted:#666;--line:#ccc}
*{box-sizing:border-box}
body{font:15px/1.45 system-ui,-apple-system,"Segoe UI",Roboto,sans-serif;color:var(--fg);margin:0;background:#fff}
main{max-width:980px;margin:0 auto;padding:12px 16px 48px}
h1{font-size:1.5em;margin:.4em 0}h2{font-size:1.2em;margin:1.6em 0 .4em;border-bottom:1px solid var(--line)}
.meta,.note-text{color:var(--muted);font-size:.9em}
code{font-size:.9em;word-break:break-all}
table{border-collapse:collapse;font-size:.84em;margin:.4em 0;width:100%}
th,td{border-bottom:1px solid #e3e3e3;padding:3px 5px;text-align:right;vertical-align:bottom}
td{overflow-wrap:normal}
th:first-child,td:first-child{text-align:left}
@media (max-width:640px){
table,thead,tbody,tr,td{display:block;width:100%}
thead{display:none}
tr{border-top:1px solid var(--line);padding:4px 0}
td{border:none;padding:1px 0;text-align:right}
td::before{content:attr(data-label);float:left;color:var(--muted);padding-right:8px;text-align:left}
td:first-child{text-align:left;font-weight:600}
td:first-child::before{content:none}
}
ul.sentences li{margin:.35em 0}
figure{margin:1em 0;break-inside:avoid;page-break-inside:avoid}
figcaption{font-size:.85em;color:var(--muted)}
svg.chart{width:100%;height:auto;display:block;font-family:inherit}
svg .title{font-size:14px;font-weight:600;fill:var(--fg)}
svg .note,svg .reflabel{font-size:10px;fill:var(--muted)}
svg .tick,svg .legend{font-size:11px;fill:#333}
svg .axis{font-size:12px;fill:#333}
svg .grid{stroke:#eee;stroke-width:1}
svg .frame{fill:none;stroke:#999;stroke-width:1}
svg .line{fill:none;stroke-width:1.6}
svg .seg{stroke-width:1.2}
svg .err{stroke-width:1;opacity:.55}
svg .box{fill-opacity:.25;stroke-width:1.4}
svg .ci{fill-opacity:.55;stroke:none}
svg .bar{fill-opacity:.35;stroke-width:.8}
svg .med{stroke-width:2.4}
svg .band{fill-opacity:.18;stroke:none}
svg .pt{fill-opacity:.8}
svg .ref{stroke:#b00;stroke-dasharray:4 3;stroke-width:1}
@media print{body{font-size:11pt}main{max-width:none;padding:0}h2{break-after:avoid}}
)";

// A value and its unit stay on one line when a cell wraps ("100.0 %", "1.2 ms").
std::string with_unit_kept(std::string text) {
  for (const std::string_view unit : {" %", " ms"})
    for (auto at = text.find(unit); at != std::string::npos; at = text.find(unit, at + 1)) text.replace(at, 1, "&#160;");
  return text;
}

std::string html_table(const std::vector<std::string>& header,
                       const std::vector<std::vector<std::string>>& rows, const std::string& name) {
  // Each cell carries its column's name (data-label): on a narrow screen the rows stack as cards, each
  // value beside its name, instead of a table wider than the page.
  std::string s = fmt::format("<table data-table=\"{}\"><thead><tr>", name);
  for (const auto& h : header) s += "<th>" + xml_escape(h) + "</th>";
  s += "</tr></thead><tbody>\n";
  for (const auto& r : rows) {
    s += "<tr>";
    for (std::size_t k = 0; k < r.size(); ++k)
      s += fmt::format("<td data-label=\"{}\">{}</td>", k < header.size() ? xml_escape(header[k]) : "",
                       with_unit_kept(xml_escape(r[k])));
    s += "</tr>\n";
  }
  return s + "</tbody></table>\n";
}

std::string figure(const std::string& svg, const std::string& caption) {
  return "<figure>\n" + svg + "<figcaption>" + xml_escape(caption) + "</figcaption></figure>\n";
}

// Box plots side by side, an empty slot between groups (BoxData::group); dashed lines at `limits`.
// `colours`: a palette index per box; empty = one colour per box in turn.
std::string boxes_svg(const std::vector<BoxData>& boxes, const std::string& chart, const std::string& title,
                      const std::string& x_label, const std::vector<stats::ThresholdShare>& limits,
                      const std::string& note, const std::vector<std::size_t>& colours = {}) {
  double lo = std::numeric_limits<double>::infinity(), hi = -lo;
  for (const auto& b : boxes) {
    if (b.n == 0) continue;
    lo = std::min(
        {lo, b.whisker_low,
         b.outliers.empty() ? b.whisker_low : *std::min_element(b.outliers.begin(), b.outliers.end())});
    hi = std::max(
        {hi, b.whisker_high,
         b.outliers.empty() ? b.whisker_high : *std::max_element(b.outliers.begin(), b.outliers.end())});
  }
  if (!(hi >= lo)) lo = 0, hi = 1;
  const double pad = (hi - lo) * 0.06 + 1e-3;
  // Positions: one slot per box, an empty slot between groups.
  std::vector<double> xs;
  double x = 0;
  for (std::size_t i = 0; i < boxes.size(); ++i) {
    if (i > 0 && boxes[i].group != boxes[i - 1].group) x += 0.6;
    xs.push_back(x);
    x += 1;
  }
  SvgPlot plot(chart, title, x_label, "latency (ms)", -0.6, x - 0.4, lo - pad, hi + pad, 720, 360);
  std::vector<std::pair<double, std::string>> cats;
  for (std::size_t i = 0; i < boxes.size(); ++i) {
    const auto& b = boxes[i];
    const auto colour = palette(colours.empty() ? i : colours.at(i));
    cats.emplace_back(xs[i], fmt::format("{} (n={})", b.scenario, b.n));
    if (b.n == 0) continue;
    const double w = 0.32;
    plot.rect(xs[i] - w, b.q1, xs[i] + w, b.q3, colour);
    if (b.median_ci && std::isfinite(b.median_ci->lower) && std::isfinite(b.median_ci->upper))
      plot.rect(xs[i] - w * 0.55, b.median_ci->lower, xs[i] + w * 0.55, b.median_ci->upper, colour, "ci");
    plot.segment(xs[i] - w, b.median, xs[i] + w, b.median, colour, "med");
    plot.segment(xs[i], b.q3, xs[i], b.whisker_high, colour);
    plot.segment(xs[i], b.q1, xs[i], b.whisker_low, colour);
    plot.segment(xs[i] - w / 2, b.whisker_high, xs[i] + w / 2, b.whisker_high, colour);
    plot.segment(xs[i] - w / 2, b.whisker_low, xs[i] + w / 2, b.whisker_low, colour);
    for (double o : b.outliers) plot.circle(xs[i], o, 2.2, colour);
  }
  for (const auto& t : limits)
    plot.hline(static_cast<double>(t.threshold.count()) / 1e6,
               fmt::format("{:g} ms", static_cast<double>(t.threshold.count()) / 1e6));
  plot.set_x_categories(std::move(cats));
  if (!note.empty()) plot.note(note);
  return plot.render();
}

std::string box_chart(const Report& report) {
  std::vector<BoxData> boxes;
  for (const auto& s : report.scenarios) boxes.push_back(box_data(s));
  std::string note;
  if (!report.groups.empty()) {
    note = "groups:";
    for (const auto& name : report.groups) note += " " + name;
  }
  return boxes_svg(boxes, "box", "Latency per scenario",
                   report.groups.empty() ? "scenario" : "scenario (grouped)",
                   report.scenarios.empty() ? std::vector<stats::ThresholdShare>{}
                                            : report.scenarios.front().result.summary.thresholds,
                   note, report.colours());
}

// The full-loop files: their table, and M2M, G2G and E2E of each file side by side.
std::string full_loop_section(const Report& report) {
  if (report.full_loops.empty()) return {};
  std::string h = "<h2>Full loop</h2>\n";
  h += html_table(full_loop_header(report.full_loops), full_loop_rows(report.full_loops), "full-loop");
  for (const auto& r : report.full_loops)
    for (const auto& note : full_loop_notes(r)) h += "<p class=\"note-text\">" + xml_escape(note) + "</p>\n";
  h += "<p class=\"note-text\">Per event: M2M = VEHICLE_GY_ON - STATION_GY_ON, G2G = PHOTOTRANSISTOR - "
       "LED_ON, "
       "E2E = M2M + G2G, motion = GY_OFF - GY_ON, each in integer ns before any statistic. Events without "
       "a value of a quantity are counted by reason: missing (an empty field), impossible (an OFF before "
       "its ON, a negative G2G), overflow.</p>\n";
  std::string files = "files, left to right:";
  for (std::size_t i = 0; i < report.full_loops.size(); ++i)
    files += (i == 0 ? " " : " | ") + report.full_loops[i].scenario;
  // One colour per quantity, the same in every file.
  const auto boxes = full_loop_boxes(report.full_loops);
  std::vector<std::size_t> colours;
  for (const auto& b : boxes) colours.push_back(b.scenario == "M2M" ? 0 : b.scenario == "G2G" ? 1 : 2);
  h += figure(boxes_svg(boxes, "full-loop", "M2M, G2G and E2E per file", "quantity (grouped by file)", {},
                        files, colours),
              "Box: quartiles; line: median; whiskers: the most extreme samples within 1.5 IQR; dots: "
              "samples beyond (at most 100 per side drawn).");
  return h;
}

std::string ecdf_chart(const Report& report) {
  double lo = std::numeric_limits<double>::infinity(), hi = -lo;
  std::vector<Curve> curves;
  for (const auto& s : report.scenarios) {
    curves.push_back(ecdf_data(s));
    if (!curves.back().x.empty()) {
      lo = std::min(lo, curves.back().x.front());
      hi = std::max(hi, curves.back().x.back());
    }
  }
  if (!(hi >= lo)) lo = 0, hi = 1;
  const double pad = (hi - lo) * 0.03 + 1e-3;
  SvgPlot plot("ecdf", "Empirical distribution (ECDF)", "latency (ms)", "fraction of samples <= latency",
               lo - pad, hi + pad, 0, 1);
  std::vector<std::pair<std::string, std::string>> legend;
  const auto colours = report.colours();
  for (std::size_t i = 0; i < curves.size(); ++i) {
    plot.step_line(curves[i].x, curves[i].y, palette(colours[i]));
    legend.emplace_back(report.scenarios[i].result.input.scenario, std::string(palette(colours[i])));
  }
  plot.legend(legend);
  return plot.render();
}

std::string histogram_chart(const Report& report) {
  const auto h = histogram_data(report);
  if (h.edges.empty()) return {};
  std::size_t top = 1;
  for (const auto& c : h.counts)
    for (auto k : c) top = std::max(top, k);
  SvgPlot plot("histogram", "Histogram", "latency (ms)", "pairs per bin", h.edges.front(), h.edges.back(), 0,
               static_cast<double>(top) * 1.08);
  std::vector<std::pair<std::string, std::string>> legend;
  const auto colours = report.colours();
  for (std::size_t i = 0; i < h.counts.size(); ++i) {
    const auto colour = palette(colours[i]);
    for (std::size_t k = 0; k < h.counts[i].size(); ++k)
      if (h.counts[i][k] > 0)
        plot.rect(h.edges[k], 0, h.edges[k + 1], static_cast<double>(h.counts[i][k]), colour, "bar");
    legend.emplace_back(report.scenarios[i].result.input.scenario, std::string(colour));
  }
  plot.legend(legend);
  plot.note(fmt::format("{} bins of {:.1f} ms over all scenarios' samples", h.edges.size() - 1,
                        h.edges[1] - h.edges[0]));
  return plot.render();
}

std::string series_chart(const ScenarioReport& s, std::size_t index, std::size_t colour_index) {
  const auto ts = time_series(s);
  if (ts.t_s.empty()) return {};
  const double lo = *std::min_element(ts.low_ms.begin(), ts.low_ms.end());
  const double hi = *std::max_element(ts.high_ms.begin(), ts.high_ms.end());
  const double pad = (hi - lo) * 0.05 + 1e-3;
  const double t_end = std::max(ts.t_s.back(), 1e-3);
  SvgPlot plot(fmt::format("timeseries-{}", index),
               fmt::format("Latency over time: {}", s.result.input.scenario), "time since the first pair (s)",
               "latency (ms)", 0, t_end, lo - pad, hi + pad, 720, 300);
  const auto colour = palette(colour_index);
  for (std::size_t i = 0; i < ts.t_s.size(); ++i) {
    if (ts.high_ms[i] > ts.low_ms[i])
      plot.segment(ts.t_s[i], ts.low_ms[i], ts.t_s[i], ts.high_ms[i], colour, "err");
    plot.circle(ts.t_s[i], ts.latency_ms[i], ts.binned ? 1.2 : 2.0, colour);
  }
  bool any_u = false;
  double u_max = 0;
  for (double u : ts.uncertainty_ms)
    if (!std::isnan(u)) any_u = true, u_max = std::max(u_max, u);
  if (ts.binned)
    plot.note(fmt::format("{} pairs in {} bins: dot = bin median, bar = bin min..max{}", ts.samples,
                          ts.t_s.size(), any_u ? fmt::format("; largest uncertainty {:.3f} ms", u_max) : ""));
  else
    plot.note(any_u ? fmt::format("bars: +/- the per-sample uncertainty (largest {:.3f} ms)", u_max)
                    : "per-sample uncertainty unknown (no clock samples)");
  return plot.render();
}

std::string clock_chart(const ScenarioReport& s, std::size_t index) {
  const auto curves = clock_curves(s);
  if (curves.empty()) return {};
  double lo = std::numeric_limits<double>::infinity(), hi = -lo, t0 = lo, t1 = -lo;
  for (const auto& c : curves)
    for (std::size_t i = 0; i < c.t_s.size(); ++i) {
      lo = std::min(lo, c.offset_ms[i] - c.bound_ms[i]);
      hi = std::max(hi, c.offset_ms[i] + c.bound_ms[i]);
      t0 = std::min(t0, c.t_s[i]);
      t1 = std::max(t1, c.t_s[i]);
    }
  const double pad = (hi - lo) * 0.05 + 1e-4;
  SvgPlot plot(fmt::format("clock-{}", index),
               fmt::format("Clock offset and error bound: {}", s.result.input.scenario),
               "time since the first pair (s)", "offset (ms)", t0, t1 > t0 ? t1 : t0 + 1, lo - pad, hi + pad,
               720, 280);
  std::vector<std::pair<std::string, std::string>> legend;
  for (std::size_t k = 0; k < curves.size(); ++k) {
    const auto& c = curves[k];
    const auto colour = palette(k * 3);  // blue and vermillion for two boards
    std::vector<double> low, high;
    for (std::size_t i = 0; i < c.t_s.size(); ++i) {
      low.push_back(c.offset_ms[i] - c.bound_ms[i]);
      high.push_back(c.offset_ms[i] + c.bound_ms[i]);
    }
    plot.band(c.t_s, low, high, colour);
    plot.polyline(c.t_s, c.offset_ms, colour);
    legend.emplace_back(fmt::format("{} ({})", c.node, c.source), std::string(colour));
  }
  plot.legend(legend);
  plot.note("line: estimated offset; band: +/- the maximum error bound");
  return plot.render();
}

// The median over the pairs in the statistics of the part of each pair's worst-case bound that is not
// its clocks' (the interrupt timestamps, the sensors' calibration, a bounce's span), ms; 0 without
// per-pair bounds.
double other_terms_ms(const ScenarioReport& s) {
  std::vector<std::int64_t> rest;
  const auto& r = s.result;
  for (std::size_t i = 0; i < r.uncertainty.size() && i < r.match.pairs.size(); ++i)
    if (r.in_statistics(i) && r.uncertainty[i].max_error_ns != analysis::kUnbounded && r.uncertainty[i].max_error_ns > 0)
      rest.push_back(r.uncertainty[i].max_error_ns - r.uncertainty[i].sync_max_ns);
  if (rest.empty()) return 0;
  std::nth_element(rest.begin(), rest.begin() + static_cast<std::ptrdiff_t>(rest.size() / 2), rest.end());
  return static_cast<double>(rest[rest.size() / 2]) / 1e6;
}

std::string budget_chart(const Report& report) {
  struct Bar {
    const ScenarioReport* s;
    double cause, effect, other;  // ms: the worst-case bound's parts
    double expanded;              // ms: U95 (k = 2), NaN when unknown
  };
  std::vector<Bar> bars;
  double top = 0;
  for (const auto& s : report.scenarios)
    if (s.result.cause_clock_ms && s.result.effect_clock_ms) {
      const double u95 = analysis::summarize_uncertainty(s.result.uncertainty, s.result.refuse_gated).median_U95_ms;
      bars.push_back({&s, *s.result.cause_clock_ms, *s.result.effect_clock_ms, other_terms_ms(s), u95});
      top = std::max({top, bars.back().cause + bars.back().effect + bars.back().other, std::isnan(u95) ? 0.0 : u95});
    }
  if (bars.empty()) return {};
  SvgPlot plot("budget", "Uncertainty of one latency (median over pairs): the worst-case bound and U95",
               "scenario", "ms", -0.6, static_cast<double>(bars.size()) - 0.4, 0, top * 1.15 + 1e-6, 720, 280);
  std::vector<std::pair<double, std::string>> cats;
  for (std::size_t i = 0; i < bars.size(); ++i) {
    const double x = static_cast<double>(i);
    const auto& b = bars[i];
    // Left: the bound, stacked by its parts; right: U95 = 2 u, the same terms combined in quadrature.
    plot.rect(x - 0.34, 0, x - 0.02, b.cause, palette(0), "bar");
    plot.rect(x - 0.34, b.cause, x - 0.02, b.cause + b.effect, palette(1), "bar");
    if (b.other > 0)
      plot.rect(x - 0.34, b.cause + b.effect, x - 0.02, b.cause + b.effect + b.other, palette(2), "bar");
    if (!std::isnan(b.expanded)) plot.rect(x + 0.02, 0, x + 0.34, b.expanded, palette(4), "bar");
    cats.emplace_back(x, b.s->result.input.scenario);
  }
  plot.set_x_categories(std::move(cats));
  plot.legend({{"bound: cause board clock", std::string(palette(0))},
               {"bound: effect board clock", std::string(palette(1))},
               {"bound: interrupts, calibration, bounces", std::string(palette(2))},
               {"U95 = 2 u (k = 2)", std::string(palette(4))}});
  return plot.render();
}

std::string ms_or_dash(const std::optional<double>& x, int d = 3) {
  return x ? fmt::format("{:.{}f}", *x, d) : "-";
}

std::string scenario_section(const Report& report) {
  std::string h = "<h2>Scenarios</h2>\n";
  std::vector<std::string> header{"scenario", "group", "pairs", "median", "IQR",
                                  "mean",     "SD",    "min",   "max",    "P95"};
  if (!report.scenarios.empty())
    for (const auto& t : report.scenarios.front().result.summary.thresholds)
      header.push_back(fmt::format("> {:g} ms", static_cast<double>(t.threshold.count()) / 1e6));
  header.push_back("median 95% CI");
  std::vector<std::vector<std::string>> rows;
  std::string resampled;  // one line per scenario: what its intervals resampled, and why
  for (const auto& s : report.scenarios) {
    const auto& m = s.result.summary;
    std::vector<std::string> r{s.result.input.scenario, s.group.empty() ? "-" : s.group};
    for (auto& cell : summary_cells(m)) r.push_back(std::move(cell));
    r.push_back(m.bootstrap ? fmt::format("{:.1f} to {:.1f}", m.bootstrap->median_ms.lower,
                                          m.bootstrap->median_ms.upper)
                            : "-");
    if (m.bootstrap)
      resampled += "<li>" + xml_escape(s.result.input.scenario + ", the CIs' resampling: " + resampling_text(m.bootstrap->resampling)) +
                   "</li>";
    rows.push_back(std::move(r));
  }
  h += html_table(header, rows, "scenarios");
  if (!resampled.empty()) h += "<ul class=\"note-text\">" + resampled + "</ul>\n";
  std::vector<std::vector<std::string>> flagged;
  for (const auto& s : report.scenarios)
    if (auto row = flagged_effect_row(s.result); !row.empty()) flagged.push_back(std::move(row));
  if (!flagged.empty()) {
    h += "<h3>What the flagged pairs do</h3>\n" + html_table(flagged_effect_header(), flagged, "flagged") +
         "<p class=\"note-text\">Median and IQR in ms, without and with the pairs the matcher flagged; "
         "\"in statistics\": the table above holds them.</p>\n";
  }
  h += "<p class=\"note-text\">Latencies in ms; type-7 quantiles; shares are of samples strictly above the "
       "limit. Ambiguous pairs are left out unless asked for.</p>\n";
  return h;
}

// The comparisons as a forest plot: each one's median difference (subject - baseline, ms) with its
// bootstrap confidence interval as a bar, zero as the reference line, and the Mann-Whitney p in its
// label. Empty without comparisons.
std::string forest_chart(const Report& report) {
  if (report.comparisons.empty()) return {};
  double lo = 0, hi = 0;
  for (const auto& r : report.comparisons) {
    const auto& c = r.comparison;
    for (const double v : {c.median_difference_ms, c.median_difference_ci_ms.lower, c.median_difference_ci_ms.upper})
      if (std::isfinite(v)) lo = std::min(lo, v), hi = std::max(hi, v);
  }
  const double pad = std::max(1.0, (hi - lo) * 0.1);
  const auto n = static_cast<double>(report.comparisons.size());
  SvgPlot plot("forest", "Median differences with their confidence intervals",
               "subject vs baseline (Mann-Whitney p)", "median difference (ms)", 0.4, n + 0.6, lo - pad, hi + pad);
  std::vector<std::pair<double, std::string>> cats;
  for (std::size_t i = 0; i < report.comparisons.size(); ++i) {
    const auto& r = report.comparisons[i];
    const auto& c = r.comparison;
    const double x = static_cast<double>(i) + 1;
    const auto colour = palette(report.colour(r.subject));
    const auto& ci = c.median_difference_ci_ms;
    if (std::isfinite(ci.lower) && std::isfinite(ci.upper)) {
      plot.segment(x, ci.lower, x, ci.upper, colour);
      plot.segment(x - 0.08, ci.lower, x + 0.08, ci.lower, colour);
      plot.segment(x - 0.08, ci.upper, x + 0.08, ci.upper, colour);
    }
    plot.circle(x, c.median_difference_ms, 3.5, colour);
    cats.emplace_back(x, fmt::format("{} vs {} ({})", r.subject, r.baseline, p_text(c.mann_whitney.p)));
  }
  plot.hline(0, "0 ms");
  plot.set_x_categories(std::move(cats));
  return plot.render();
}

std::string comparison_section(const Report& report) {
  std::string h;
  if (!report.comparisons.empty()) {
    h += "<h2>Comparisons</h2>\n<ul class=\"sentences\">\n";
    for (const auto& c : report.comparisons) h += "<li>" + xml_escape(comparison_sentence(c)) + "</li>\n";
    h += "</ul>\n";
    std::vector<std::vector<std::string>> crows;
    const auto ci = [](const stats::Interval& i, int d) {
      return std::isnan(i.lower) ? std::string("-")
                                 : fmt::format("{:.{}f} to {:.{}f}", i.lower, d, i.upper, d);
    };
    for (const auto& r : report.comparisons) {
      const auto& c = r.comparison;
      crows.push_back({r.subject + " vs " + r.baseline, fmt::format("{:+.1f}", c.median_difference_ms),
                       ci(c.median_difference_ci_ms, 1), p_text(c.mann_whitney.p),
                       fmt::format("{:.3f}", c.iqr_ratio), ci(c.iqr_ratio_ci, 3),
                       fmt::format("{:.3f}", c.sd_ratio), ci(c.sd_ratio_ci, 3), p_text(c.brown_forsythe.p),
                       ms_or_dash(c.uncertainty_ms)});
    }
    h += html_table({"subject vs baseline", "median diff (ms)", "CI", "Mann-Whitney", "IQR ratio", "CI",
                     "SD ratio", "CI", "Brown-Forsythe", "uncertainty (ms)"},
                    crows, "comparisons");
    h += figure(forest_chart(report),
                "Dot: the difference of the medians (subject - baseline); bar: its bootstrap confidence "
                "interval; p: the Mann-Whitney test of the two samples' locations.");
  }

  return h;
}

// The stages of each scenario's events, when the report was given markers and a stage rule.
std::string breakdown_section(const Report& report) {
  BreakdownResults results;
  for (const auto& s : report.scenarios)
    if (s.result.breakdown) results.push_back(&s.result);
  if (results.empty()) return {};
  std::string h = "<h2>Where the time goes</h2>\n";
  h += figure(breakdown_svg(results),
              "Each bar: one scenario's complete events; each block: the mean of one stage (ms), from the cause "
              "edge through the markers of the stage rule to the effect edge, so the blocks add up to the mean "
              "M2M. The table gives each stage's median and quartiles.");
  h += "<pre class=\"breakdown\">" + xml_escape(breakdown_table(results)) + "</pre>\n";
  return h;
}

std::string distribution_sections(const Report& report) {
  std::string h = "<h2>Distributions</h2>\n";
  h += figure(box_chart(report),
              "Box: quartiles; line: median; dark band: the median's bootstrap confidence interval; "
              "whiskers: the most extreme samples within 1.5 IQR; dots: samples beyond (at most 100 per "
              "side drawn); dashed: latency limits; n: the pairs in the statistics.");
  h += figure(ecdf_chart(report), "Share of samples at or below each latency.");
  if (auto hist = histogram_chart(report); !hist.empty()) h += figure(hist, "Counts per bin, all samples.");

  h += "<h2>Latency over time</h2>\n";
  const auto colours = report.colours();
  for (std::size_t i = 0; i < report.scenarios.size(); ++i)
    if (auto c = series_chart(report.scenarios[i], i, colours[i]); !c.empty())
      h += figure(
          c,
          "Each pair at its cause edge's time; bars show the per-sample expanded uncertainty U95 (k = 2, "
          "docs/precision.md) or, for long series, each bin's range.");

  bool any_clock = false;
  for (const auto& s : report.scenarios) any_clock |= !s.result.clocks.empty();
  h += "<h2>Clocks</h2>\n";
  if (!any_clock) h += "<p class=\"note-text\">No clock samples in the inputs (data files carry none).</p>\n";
  for (std::size_t i = 0; i < report.scenarios.size(); ++i)
    if (auto c = clock_chart(report.scenarios[i], i); !c.empty())
      h += figure(c,
                  "Per board: the clock's estimated offset from its reference and its maximum error bound.");

  h += "<h2>Error budget</h2>\n";
  if (auto b = budget_chart(report); !b.empty()) {
    h += figure(
        b,
        "Left: the median per-pair worst-case bound on a latency's error (the two boards' clock bounds, then "
        "the interrupts, the calibration and bounces); right: the median U95 = 2 u of the same terms in "
        "quadrature, about 95 % of true latencies within it (docs/precision.md, one sample through the three "
        "numbers).");
    std::vector<std::vector<std::string>> brows;
    for (const auto& s : report.scenarios)
      brows.push_back({s.result.input.scenario, ms_or_dash(s.result.cause_clock_ms),
                       ms_or_dash(s.result.effect_clock_ms), ms_or_dash(s.median_bound_ms()),
                       ms_or_dash(s.median_uncertainty_ms())});
    h += html_table(
        {"scenario", "cause clock (ms)", "effect clock (ms)", "median bound (ms)", "median U95 (ms)"}, brows,
        "budget");
  } else {
    h += fmt::format("<p class=\"note-text\">Unknown: no clock samples{}.</p>\n",
                     report.assumed_uncertainty_ms
                         ? fmt::format("; comparisons assume {:.3f} ms per latency (--uncertainty)",
                                       *report.assumed_uncertainty_ms)
                         : "");
  }

  h += "<h2>Losses and unmatched edges</h2>\n";
  std::vector<std::vector<std::string>> lrows;
  for (const auto& s : report.scenarios) {
    const auto c = analysis::pairing_counts(s.result);
    std::string recorded = s.result.losses.empty() ? "none recorded" : "";
    for (const auto& l : s.result.losses)
      recorded += fmt::format("{}{}: {} {} ({} records)", recorded.empty() ? "" : "; ", l.node, l.events,
                              l.kind, l.records);
    lrows.push_back({s.result.input.scenario, std::to_string(c.cause.edges), std::to_string(c.effect.edges),
                     std::to_string(c.pairs), std::to_string(c.flagged), std::to_string(c.in_statistics),
                     fmt::format("{} / {}", c.cause.no_candidate, c.cause.outmatched),
                     fmt::format("{} / {}", c.effect.no_candidate, c.effect.outmatched),
                     fmt::format("{} / {}", c.cause.bounces, c.effect.bounces), recorded});
  }
  h += html_table({"scenario", "cause edges", "effect edges", "pairs", "flagged", "in statistics",
                   "cause unmatched (no candidate / outmatched)", "effect unmatched (no candidate / outmatched)",
                   "bounces (cause / effect)", "recorded losses"},
                  lrows, "losses");
  // The sanity verdict (analysis/sanity.hpp) and the events left out on no known clock, in words.
  for (const auto& s : report.scenarios) {
    const auto& in = s.result.input;
    for (const auto& w : s.result.warnings)
      h += "<p class=\"note-text\"><strong>warning:</strong> " + xml_escape(in.scenario + ": " + w.text) + "</p>\n";
    if (const auto left = in.cause_unknown_clock.total() + in.effect_unknown_clock.total(); left != 0)
      h += "<p class=\"note-text\">" +
           xml_escape(fmt::format("{}: {} events left out before pairing, their stamps on no known clock "
                                  "(docs/sync.md)",
                                  in.scenario, left)) +
           "</p>\n";
  }
  // Clock steps (docs/sync.md): only where a board's clock stepped.
  std::vector<std::vector<std::string>> srows;
  std::vector<std::string> slew_notes;
  for (const auto& s : report.scenarios) {
    for (const auto& note : clock_limit_notes(s.result)) slew_notes.push_back(s.result.input.scenario + ": " + note);
    if (s.result.steps.steps() != 0 || s.result.steps.limited())
      srows.push_back({s.result.input.scenario, std::to_string(s.result.steps.cause.steps),
                       std::to_string(s.result.steps.effect.steps),
                       std::to_string(s.result.pairs_marked(analysis::StepMark::corrected)),
                       std::to_string(s.result.pairs_marked(analysis::StepMark::unknown))});
  }
  if (!srows.empty()) {
    h += "<h2>Clock steps</h2>\n";
    h += html_table({"scenario", "cause steps", "effect steps", "pairs corrected by the step's known size",
                     "pairs after a step of unknown size (left out)"},
                    srows, "clock-steps");
    for (const auto& note : slew_notes) h += "<p class=\"note-text\">" + xml_escape(note) + "</p>\n";
  }
  return h;
}

}  // namespace

std::string report_html(const Report& report) {
  std::string h =
      "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n"
      "<meta name=\"viewport\" content=\"width=device-width, initial-scale=1\">\n"
      "<title>m2mlat latency report</title>\n<style>" +
      std::string(kCss) + "</style>\n</head>\n<body>\n<main>\n<h1>Latency report</h1>\n";
  h += "<p class=\"meta\">Produced by <code>" + xml_escape(report.command) + "</code>";
  for (const auto& [name, version] : report.versions)
    h += "; " + xml_escape(name) + " " + xml_escape(version);
  h += ".</p>\n";

  // The matcher's scenarios: their sections are left out when only full-loop files were given.
  const bool scenarios = !report.scenarios.empty() || report.full_loops.empty();
  if (scenarios) h += scenario_section(report);
  h += full_loop_section(report);
  h += comparison_section(report);
  if (scenarios) h += distribution_sections(report);
  h += breakdown_section(report);
  h += "<p class=\"meta\">Every number and chart is recomputed from the raw events by the command above; "
       "re-run it "
       "with other matcher windows, thresholds or groups to change them.</p>\n";
  return h + "</main>\n</body>\n</html>\n";
}

}  // namespace m2mlat::report
