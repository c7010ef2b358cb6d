// pgfplots figures from plot_data: box plots (boxplot prepared, outliers from a data file), ECDF
// (const plot), histogram (ybar interval), latency over time (error bars), clock offset (bands).
#include "m2mlat/report/pgfplots.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "m2mlat/core/error.hpp"
#include "m2mlat/core/output_file.hpp"
#include "m2mlat/report/breakdown_view.hpp"
#include "m2mlat/report/comparison_text.hpp"
#include "m2mlat/report/full_loop_view.hpp"
#include "m2mlat/report/plot_data.hpp"
#include "m2mlat/report/svg_plot.hpp"

namespace m2mlat::report {

namespace {

constexpr const char* kColours[] = {"blue!70!black", "orange!90!black", "green!50!black", "red!75!black",
                                    "violet",        "cyan!70!black",   "olive",          "black"};
const char* colour(std::size_t i) { return kColours[i % 8]; }

class Writer {
 public:
  explicit Writer(std::filesystem::path dir) : dir_(std::move(dir)) {}
  void file(const std::string& name, const std::string& text) {
    core::write_output_file((dir_ / name).string(), text);
    names_.push_back(name);
  }
  std::vector<std::string> names_;

 private:
  std::filesystem::path dir_;
};

std::string header(const std::string& what) {
  return fmt::format(
      "% {} -- written by m2mlat report; data in the .dat files beside it.\n"
      "% Needs \\usepackage{{pgfplots}} \\usepgfplotslibrary{{statistics}}; define \\mtwomlatdir if the "
      "files\n"
      "% are in another folder than the document (\\newcommand\\mtwomlatdir{{figures/}}).\n"
      "\\providecommand\\mtwomlatdir{{}}%\n",
      what);
}

std::string num(double x) { return std::isnan(x) ? "nan" : fmt::format("{:.6f}", x); }

// About six round tick positions within [low, high] (svg_plot's rule) as a pgfplots list: ybar interval
// would otherwise label every bin edge.
std::string tick_list(double low, double high) {
  std::string out;
  for (const double t : nice_ticks(low, high)) out += (out.empty() ? "" : ",") + fmt::format("{:g}", t);
  return out;
}

// The thresholds of the statistics (the first scenario's: every scenario has the same) as dashed
// horizontal lines across a box plot, each labelled at its right end, as in the HTML report.
std::string threshold_lines(const Report& report) {
  std::string out;
  if (report.scenarios.empty()) return out;
  for (const auto& t : report.scenarios.front().result.summary.thresholds) {
    const double ms = static_cast<double>(t.threshold.count()) / 1e6;
    out += fmt::format(
        "\\draw[dashed, gray] ({{rel axis cs:0,0}} |- {{axis cs:0,{0:g}}}) -- ({{rel axis cs:1,0}} |- "
        "{{axis cs:0,{0:g}}}) node[pos=1, above left, font=\\scriptsize] {{{0:g} ms}};\n",
        ms);
  }
  return out;
}

}  // namespace

std::string tex_escape(const std::string& text) {
  std::string out;
  for (char ch : text) switch (ch) {
      case '_':
      case '%':
      case '&':
      case '#':
      case '$':
      case '{':
      case '}':
        out += '\\';
        out += ch;
        break;
      case '~': out += "\\textasciitilde{}"; break;
      case '^': out += "\\textasciicircum{}"; break;
      case '\\': out += "\\textbackslash{}"; break;
      default: out += ch;
    }
  return out;
}

std::vector<std::string> write_pgfplots(const Report& report, const std::filesystem::path& directory) {
  const auto colours = report.colours();  // each scenario's, as in the HTML report's figures
  std::error_code ec;
  std::filesystem::create_directories(directory, ec);
  if (ec)
    throw core::Error(core::ErrorKind::io,
                      fmt::format("{}: cannot create: {}", directory.string(), ec.message()));
  Writer w(directory);
  std::vector<std::string> figures;

  // The matcher's scenarios' figures are left out when only full-loop files were given.
  const bool scenarios = !report.scenarios.empty() || report.full_loops.empty();

  // Box plots, one per scenario, grouped with a gap between groups.
  if (scenarios) {
    std::string dat = "scenario group n lower_whisker q1 median q3 upper_whisker outliers\n";
    std::string tex =
        header("Box plot of latency per scenario") +
        "\\begin{tikzpicture}\n\\begin{axis}[width=0.95\\linewidth, height=6cm, ylabel={latency (ms)},\n"
        "  boxplot/draw direction=y, xtick={";
    std::string ticks, labels, plots;
    double x = 1;
    for (std::size_t i = 0; i < report.scenarios.size(); ++i) {
      const auto b = box_data(report.scenarios[i]);
      if (i > 0 && report.scenarios[i].group != report.scenarios[i - 1].group) x += 0.6;
      const auto name = file_part(b.scenario);
      dat += fmt::format("{} {} {} {} {} {} {} {} {}\n", name, b.group.empty() ? "-" : file_part(b.group),
                         b.n, num(b.whisker_low), num(b.q1), num(b.median), num(b.q3), num(b.whisker_high),
                         b.outlier_count);
      std::string out = "outlier_ms\n";
      for (double o : b.outliers) out += num(o) + "\n";
      w.file(fmt::format("box-outliers-{}.dat", name), out);
      ticks += fmt::format("{}{:g}", i ? "," : "", x);
      labels += fmt::format("{}{{{} ($n$={})}}", i ? "," : "", tex_escape(b.scenario), b.n);
      if (b.n > 0)
        plots += fmt::format(
            "\\addplot+[{}, solid, mark=o, mark size=1pt, boxplot prepared={{draw position={:g}, lower "
            "whisker={}, "
            "lower quartile={}, median={}, upper quartile={}, upper whisker={}}}] table[y=outlier_ms] "
            "{{\\mtwomlatdir box-outliers-{}.dat}};\n",
            colour(colours[i]), x, num(b.whisker_low), num(b.q1), num(b.median), num(b.q3), num(b.whisker_high), name);
      x += 1;
    }
    tex += ticks + "}, xticklabels={" + labels + "}, x tick label style={rotate=20, anchor=north east}]\n" +
           plots + threshold_lines(report) + "\\end{axis}\n\\end{tikzpicture}\n";
    w.file("box.dat", dat);
    w.file("box.tex", tex);
    figures.push_back("box.tex");
  }

  // The full-loop files: M2M, G2G and E2E of each file side by side, a gap between files.
  if (!report.full_loops.empty()) {
    std::string dat = "file quantity n lower_whisker q1 median q3 upper_whisker outliers\n";
    std::string tex =
        header("Box plot of M2M, G2G and E2E per full-loop file") +
        "\\begin{tikzpicture}\n\\begin{axis}[width=0.95\\linewidth, height=6cm, ylabel={latency (ms)},\n"
        "  boxplot/draw direction=y, xtick={";
    std::string ticks, labels, plots;
    double x = 1;
    const auto boxes = full_loop_boxes(report.full_loops);
    for (std::size_t i = 0; i < boxes.size(); ++i) {
      const auto& b = boxes[i];
      if (i > 0 && b.group != boxes[i - 1].group) x += 0.6;
      const auto name = file_part(b.group) + "-" + file_part(b.scenario);
      dat += fmt::format("{} {} {} {} {} {} {} {} {}\n", file_part(b.group), file_part(b.scenario), b.n,
                         num(b.whisker_low), num(b.q1), num(b.median), num(b.q3), num(b.whisker_high),
                         b.outlier_count);
      std::string out = "outlier_ms\n";
      for (double o : b.outliers) out += num(o) + "\n";
      w.file(fmt::format("full-loop-outliers-{}.dat", name), out);
      ticks += fmt::format("{}{:g}", i ? "," : "", x);
      labels += fmt::format("{}{{{} {}}}", i ? "," : "", tex_escape(b.scenario), tex_escape(b.group));
      if (b.n > 0)
        plots += fmt::format(
            "\\addplot+[{}, solid, mark=o, mark size=1pt, boxplot prepared={{draw position={:g}, lower "
            "whisker={}, lower quartile={}, median={}, upper quartile={}, upper whisker={}}}] "
            "table[y=outlier_ms] {{\\mtwomlatdir full-loop-outliers-{}.dat}};\n",
            colour(i), x, num(b.whisker_low), num(b.q1), num(b.median), num(b.q3), num(b.whisker_high), name);
      x += 1;
    }
    tex += ticks + "}, xticklabels={" + labels + "}, x tick label style={rotate=20, anchor=north east}]\n" +
           plots + "\\end{axis}\n\\end{tikzpicture}\n";
    w.file("full-loop.dat", dat);
    w.file("full-loop.tex", tex);
    figures.push_back("full-loop.tex");
  }

  // ECDF.
  if (scenarios) {
    std::string tex =
        header("Empirical distribution functions") +
        "\\begin{tikzpicture}\n\\begin{axis}[width=0.95\\linewidth, height=6cm, xlabel={latency (ms)},\n"
        "  ylabel={fraction $\\le$ latency}, ymin=0, ymax=1, legend pos=south east, legend cell "
        "align=left]\n";
    for (std::size_t i = 0; i < report.scenarios.size(); ++i) {
      const auto c = ecdf_data(report.scenarios[i]);
      const auto name = file_part(report.scenarios[i].result.input.scenario);
      std::string dat = "latency_ms fraction\n";
      for (std::size_t k = 0; k < c.x.size(); ++k) dat += fmt::format("{} {:.6f}\n", num(c.x[k]), c.y[k]);
      w.file(fmt::format("ecdf-{}.dat", name), dat);
      if (c.x.empty()) continue;
      tex += fmt::format(
          "\\addplot[{}, thick, const plot] table[x=latency_ms, y=fraction] {{\\mtwomlatdir ecdf-{}.dat}};\n"
          "\\addlegendentry{{{}}}\n",
          colour(colours[i]), name, tex_escape(report.scenarios[i].result.input.scenario));
    }
    w.file("ecdf.tex", tex + "\\end{axis}\n\\end{tikzpicture}\n");
    figures.push_back("ecdf.tex");
  }

  // Histogram over common bins.
  if (const auto h = histogram_data(report); !h.edges.empty()) {
    std::string dat = "left_ms";
    for (std::size_t i = 0; i < report.scenarios.size(); ++i) dat += fmt::format(" c{}", i);
    dat += "\n";
    for (std::size_t k = 0; k < h.edges.size(); ++k) {
      dat += num(h.edges[k]);
      // ybar interval takes the last row as the right edge of the last bin.
      for (const auto& c : h.counts)
        dat += fmt::format(" {}", k + 1 < h.edges.size() ? c[k] : (c.empty() ? 0 : c.back()));
      dat += "\n";
    }
    w.file("histogram.dat", dat);
    std::string tex =
        header("Histogram of latency") +
        "\\begin{tikzpicture}\n\\begin{axis}[width=0.95\\linewidth, height=6cm, xlabel={latency (ms)},\n"
        "  ylabel={pairs per bin}, ymin=0, ybar interval, legend cell align=left,\n"
        "  x tick label as interval=false, xtick={" + tick_list(h.edges.front(), h.edges.back()) +
        "}, xticklabel style={/pgf/number format/fixed}]\n";
    for (std::size_t i = 0; i < report.scenarios.size(); ++i)
      tex += fmt::format(
          "\\addplot[draw={0}, fill={0}, fill opacity=0.3] table[x=left_ms, y=c{1}] "
          "{{\\mtwomlatdir histogram.dat}};\n\\addlegendentry{{{2}}}\n",
          colour(colours[i]), i, tex_escape(report.scenarios[i].result.input.scenario));
    w.file("histogram.tex", tex + "\\end{axis}\n\\end{tikzpicture}\n");
    figures.push_back("histogram.tex");
  }

  // The comparisons: median differences with their confidence intervals (a forest plot), zero dashed.
  if (!report.comparisons.empty()) {
    std::string dat = "index difference_ms minus_ms plus_ms mann_whitney_p\n", labels;
    for (std::size_t i = 0; i < report.comparisons.size(); ++i) {
      const auto& r = report.comparisons[i];
      const auto& c = r.comparison;
      const auto& ci = c.median_difference_ci_ms;
      const bool with_ci = std::isfinite(ci.lower) && std::isfinite(ci.upper);
      dat += fmt::format("{} {} {} {} {:g}\n", i + 1, num(c.median_difference_ms),
                         num(with_ci ? c.median_difference_ms - ci.lower : 0.0),
                         num(with_ci ? ci.upper - c.median_difference_ms : 0.0), c.mann_whitney.p);
      labels += fmt::format("{}{{{} vs {} ({})}}", i ? "," : "", tex_escape(r.subject), tex_escape(r.baseline),
                            tex_escape(p_text(c.mann_whitney.p)));
    }
    w.file("forest.dat", dat);
    w.file("forest.tex",
           header("Median differences with their confidence intervals") +
               fmt::format("\\begin{{tikzpicture}}\n\\begin{{axis}}[width=0.95\\linewidth, height=6cm, "
                           "ylabel={{median difference (ms)}}, xmin=0.5, xmax={}, xtick={{1,...,{}}},\n"
                           "  xticklabels={{{}}}, x tick label style={{rotate=20, anchor=north east}}]\n"
                           "\\addplot[only marks, mark=*, error bars/.cd, y dir=both, y explicit]\n"
                           "  table[x=index, y=difference_ms, y error plus=plus_ms, y error minus=minus_ms] "
                           "{{\\mtwomlatdir forest.dat}};\n"
                           "\\draw[dashed, gray] ({{rel axis cs:0,0}} |- {{axis cs:0,0}}) -- ({{rel axis cs:1,0}} "
                           "|- {{axis cs:0,0}});\n\\end{{axis}}\n\\end{{tikzpicture}}\n",
                           static_cast<double>(report.comparisons.size()) + 0.5, report.comparisons.size(), labels));
    figures.push_back("forest.tex");
  }

  // Latency over time and clocks, per scenario.
  for (std::size_t i = 0; i < report.scenarios.size(); ++i) {
    const auto& s = report.scenarios[i];
    const auto name = file_part(s.result.input.scenario);
    const auto ts = time_series(s);
    if (!ts.t_s.empty()) {
      std::string dat = "time_s latency_ms minus_ms plus_ms\n";
      for (std::size_t k = 0; k < ts.t_s.size(); ++k)
        dat += fmt::format("{:.6f} {} {} {}\n", ts.t_s[k], num(ts.latency_ms[k]),
                           num(ts.latency_ms[k] - ts.low_ms[k]), num(ts.high_ms[k] - ts.latency_ms[k]));
      w.file(fmt::format("timeseries-{}.dat", name), dat);
      w.file(fmt::format("timeseries-{}.tex", name),
             header(fmt::format("Latency over time, {}", s.result.input.scenario)) +
                 fmt::format("\\begin{{tikzpicture}}\n\\begin{{axis}}[width=0.95\\linewidth, height=5cm, "
                             "xlabel={{time (s)}}, ylabel={{latency (ms)}}, title={{{}}}]\n"
                             "\\addplot[{}, only marks, mark=*, mark size=0.8pt, error bars/.cd, y dir=both, "
                             "y explicit]\n"
                             "  table[x=time_s, y=latency_ms, y error plus=plus_ms, y error minus=minus_ms] "
                             "{{\\mtwomlatdir timeseries-{}.dat}};\n\\end{{axis}}\n\\end{{tikzpicture}}\n",
                             tex_escape(s.result.input.scenario), colour(colours[i]), name));
      figures.push_back(fmt::format("timeseries-{}.tex", name));
    }
    const auto clocks = clock_curves(s);
    if (!clocks.empty()) {
      std::string tex =
          header(fmt::format("Clock offset and error bound, {}", s.result.input.scenario)) +
          fmt::format(
              "\\begin{{tikzpicture}}\n\\begin{{axis}}[width=0.95\\linewidth, height=5cm, "
              "xlabel={{time (s)}}, ylabel={{offset (ms)}}, title={{{}}}, legend cell align=left]\n",
              tex_escape(s.result.input.scenario));
      for (std::size_t k = 0; k < clocks.size(); ++k) {
        const auto& c = clocks[k];
        const auto file = fmt::format("clock-{}-{}.dat", name, file_part(c.node));
        std::string dat = "time_s offset_ms bound_ms low_ms high_ms\n";
        for (std::size_t j = 0; j < c.t_s.size(); ++j)
          dat += fmt::format("{:.6f} {} {} {} {}\n", c.t_s[j], num(c.offset_ms[j]), num(c.bound_ms[j]),
                             num(c.offset_ms[j] - c.bound_ms[j]), num(c.offset_ms[j] + c.bound_ms[j]));
        w.file(file, dat);
        tex += fmt::format(
            "\\addplot[{0}, thin, forget plot] table[x=time_s, y=low_ms] {{\\mtwomlatdir {1}}};\n"
            "\\addplot[{0}, thin, forget plot] table[x=time_s, y=high_ms] {{\\mtwomlatdir {1}}};\n"
            "\\addplot[{0}, thick] table[x=time_s, y=offset_ms] {{\\mtwomlatdir {1}}};\n"
            "\\addlegendentry{{{2}}}\n",
            colour(k * 3), file, tex_escape(c.node));
      }
      w.file(fmt::format("clock-{}.tex", name), tex + "\\end{axis}\n\\end{tikzpicture}\n");
      figures.push_back(fmt::format("clock-{}.tex", name));
    }
  }

  BreakdownResults breakdowns;
  for (const auto& s : report.scenarios)
    if (s.result.breakdown) breakdowns.push_back(&s.result);
  for (const auto& [file, text] : breakdown_pgfplots(breakdowns)) {
    w.file(file, text);
    if (file.ends_with(".tex")) figures.push_back(file);
  }

  std::string doc =
      "% All figures of the report in one document: pdflatex figures.tex\n"
      "\\documentclass{article}\n\\usepackage[margin=2cm]{geometry}\n\\usepackage{pgfplots}\n"
      "\\usepgfplotslibrary{statistics}\n\\pgfplotsset{compat=1.16}\n\\begin{document}\n";
  for (const auto& f : figures)
    doc += fmt::format("\\begin{{figure}}[p]\\centering\n\\input{{{}}}\n\\end{{figure}}\n", f);
  w.file("figures.tex", doc + "\\end{document}\n");
  return w.names_;
}

}  // namespace m2mlat::report
