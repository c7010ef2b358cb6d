// A report's comparisons and its folder of files (see report_files.hpp).
#include "m2mlat/cli/report_files.hpp"

#include <fmt/format.h>
#include <sqlite3.h>

#include <boost/version.hpp>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "m2mlat/cli/output.hpp"
#include "m2mlat/core/error.hpp"
#include "m2mlat/core/output_file.hpp"
#include "m2mlat/core/version.hpp"
#include "m2mlat/report/breakdown_view.hpp"
#include "m2mlat/report/full_loop_view.hpp"
#include "m2mlat/report/html_report.hpp"
#include "m2mlat/report/pgfplots.hpp"
#include "m2mlat/report/report_json.hpp"
#include "m2mlat/report/report_tables.hpp"

namespace m2mlat::cli {

namespace {

// The command line as the user typed it, shell-quoted where needed (from /proc/self/cmdline).
std::string command_line() {
  std::ifstream in("/proc/self/cmdline", std::ios::binary);
  std::stringstream buffer;
  buffer << in.rdbuf();
  const auto all = buffer.str();
  std::string out;
  std::size_t start = 0;
  bool first = true;
  while (start < all.size()) {
    auto end = all.find('\0', start);
    if (end == std::string::npos) end = all.size();
    auto arg = all.substr(start, end - start);
    if (first) arg = std::filesystem::path(arg).filename().string();  // "m2mlat", not the build path
    const bool plain = !arg.empty() && arg.find_first_not_of(
                                           "abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ"
                                           "0123456789-_./=:,+@%") == std::string::npos;
    if (!first) out += ' ';
    if (plain) {
      out += arg;
    } else {
      out += '\'';
      for (char ch : arg) out += ch == '\'' ? std::string("'\\''") : std::string(1, ch);
      out += '\'';
    }
    first = false;
    start = end + 1;
  }
  return out.empty() ? "m2mlat" : out;
}

}  // namespace

report::Report new_report() {
  report::Report r;
  r.command = command_line();
  r.versions = {{"m2mlat", core::kVersion},
                {"compiler", __VERSION__},
                {"Boost", fmt::format("{}.{}", BOOST_VERSION / 100000, BOOST_VERSION / 100 % 1000)},
                {"SQLite", sqlite3_libversion()}};
  return r;
}

void add_comparisons(report::Report& r, const std::vector<std::string>& compares, bool no_compare,
                     const StatsFlags& stats, const std::string& baseline) {
  std::vector<std::pair<std::string, std::string>> pairs;
  for (const auto& spec : compares) {
    const auto colon = spec.find(':');
    if (colon == std::string::npos || colon == 0 || colon + 1 == spec.size())
      throw core::Error(core::ErrorKind::usage,
                        fmt::format("--compare '{}': expected SUBJECT:BASELINE", spec));
    pairs.emplace_back(spec.substr(0, colon), spec.substr(colon + 1));
  }
  if (pairs.empty() && !no_compare) {
    // Default comparisons skip a scenario with too few latencies (an explicit --compare fails on it).
    for (const auto& [subject, base] : report::default_comparisons(r, baseline)) {
      const auto too_few = [&](const std::string& name) { return r.find(name)->result.summary.n < 2; };
      if (too_few(subject) || too_few(base))
        warn(fmt::format("{} vs {} not compared: fewer than 2 latencies", subject, base));
      else
        pairs.emplace_back(subject, base);
    }
  }
  stats::CompareOptions options;
  const auto summary_options = stats.options();
  options.thresholds = summary_options.thresholds;
  options.resamples = stats.bootstrap;
  options.seed = stats.seed;
  options.level = stats.level;
  // The full-loop files compare among themselves, quantity by quantity (report_model.hpp).
  if (compares.empty() && !no_compare)
    for (auto& p : report::default_full_loop_comparisons(r)) pairs.push_back(std::move(p));
  for (const auto& [subject, base] : pairs) {
    progress(fmt::format("comparing {} with {}", subject, base));
    if (r.find_full_loop(subject) != nullptr && r.find_full_loop(base) != nullptr) {
      for (auto& one : report::compare_full_loops(r, subject, base, options)) r.comparisons.push_back(std::move(one));
      continue;
    }
    r.comparisons.push_back(report::compare_scenarios(r, subject, base, options));
  }
}

void write_report_folder(const report::Report& r, const std::string& dir_name) {
  const std::filesystem::path dir(dir_name);
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  if (ec) throw core::Error(core::ErrorKind::io, fmt::format("{}: cannot create: {}", dir_name, ec.message()));
  core::write_output_file((dir / "report.html").string(), report::report_html(r));
  core::write_output_file((dir / "report.md").string(), report::report_markdown(r));
  core::write_output_file((dir / "report.json").string(), json_text(report::report_document(r)) + "\n");
  core::write_output_file((dir / "scenarios.csv").string(), report::scenarios_csv(r));
  core::write_output_file((dir / "comparisons.csv").string(), report::comparisons_csv(r));
  if (!r.full_loops.empty())
    core::write_output_file((dir / "full_loop.csv").string(), report::full_loop_csv(r.full_loops));
  report::BreakdownResults breakdowns;
  for (const auto& s : r.scenarios)
    if (s.result.breakdown) breakdowns.push_back(&s.result);
  if (!breakdowns.empty())
    core::write_output_file((dir / "breakdown.csv").string(), report::breakdown_csv(breakdowns));
  report::write_pgfplots(r, dir / "pgfplots");
}

}  // namespace m2mlat::cli
