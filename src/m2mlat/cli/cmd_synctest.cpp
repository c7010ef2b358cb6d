// `m2mlat synctest`: how far apart two boards' clocks are, from one pulse line seen by both
// (selftest/synctest.hpp). Inputs: two stores (one board each), one store with both boards' nodes,
// an events file with both, or the reference rig's sync-test CSV.
#include <fmt/format.h>

#include <cmath>
#include <filesystem>
#include <limits>
#include <memory>
#include <set>

#include "m2mlat/cli/command.hpp"
#include "m2mlat/cli/duration_flag.hpp"
#include "m2mlat/cli/inputs.hpp"
#include "m2mlat/cli/output.hpp"
#include "m2mlat/core/error.hpp"
#include "m2mlat/core/output_file.hpp"
#include "m2mlat/core/printable.hpp"
#include "m2mlat/formats/import_file.hpp"
#include "m2mlat/report/svg_plot.hpp"
#include "m2mlat/report/table.hpp"
#include "m2mlat/selftest/synctest.hpp"
#include "m2mlat/store/store.hpp"

namespace m2mlat::cli {

namespace {

struct SynctestCommand {
  std::vector<std::string> inputs;
  std::string a_node, b_node;
  std::string channel = "pulse";
  std::string edge = "both";
  std::string period;           // empty: estimated
  std::string expected_offset;  // empty: 0
  std::string tau0;             // empty: the median spacing
  double growth_ppm = 15;
  bool json = false;
  bool series = false;
  std::string csv_out, svg_out;
};

// One board's side: its edges on the pulse channel and its clock samples.
struct Board {
  std::string label;
  std::vector<std::int64_t> t_ns;
  analysis::ClockTrack clock;
};

std::optional<core::Edge> edge_filter(const std::string& edge) {
  if (edge == "both") return std::nullopt;
  return core::parse_edge(edge);
}

// The nodes of `store` with events on `channel`.
std::set<std::string> pulse_nodes(const store::Store& store, const std::string& channel) {
  std::set<std::string> nodes;
  for (const auto& s : store.sessions())
    for (const auto& c : store.channels(s.id))
      if (c == channel) nodes.insert(s.node);
  return nodes;
}

Board load_board(const store::Store& store, const std::string& node, const SynctestCommand& c) {
  Board board;
  board.label = fmt::format("{}:{}/{}", store.path(), node, c.channel);
  store::EventFilter filter;
  filter.node = node;
  filter.channel = c.channel;
  filter.edge = edge_filter(c.edge);
  const auto ts = store.timestamps(
      core::TimePoint::from_ns(core::Clock::realtime, std::numeric_limits<std::int64_t>::min()),
      core::TimePoint::from_ns(core::Clock::realtime, std::numeric_limits<std::int64_t>::max()), filter);
  board.t_ns = ts.t_ns;
  if (board.t_ns.empty())
    throw core::Error(core::ErrorKind::data, fmt::format("{}: no CLOCK_REALTIME {} edges of {}/{}",
                                                         store.path(), c.edge, node, c.channel));
  std::vector<store::ClockSample> samples;
  for (const auto& s : store.sessions())
    if (s.node == node)
      for (auto& cs : store.clock_samples(s.id)) samples.push_back(std::move(cs));
  board.clock = analysis::make_clock_track(std::move(samples));
  return board;
}

std::string only_node(const store::Store& store, const std::string& channel, const std::string& given) {
  if (!given.empty()) return given;
  const auto nodes = pulse_nodes(store, channel);
  if (nodes.empty())
    throw core::Error(core::ErrorKind::data,
                      fmt::format("{}: no node has events on channel '{}'", store.path(), channel));
  if (nodes.size() != 1)
    throw core::Error(core::ErrorKind::usage,
                      fmt::format("{}: {} nodes have events on channel '{}': choose one with --a/--b",
                                  store.path(), nodes.size(), channel));
  return *nodes.begin();
}

selftest::SyncTestResult run(const SynctestCommand& c) {
  selftest::SyncTestOptions options;
  options.tau0 = duration_flag("--tau0", c.tau0, true);
  pairing::PulsePairingOptions pairing_options;
  pairing_options.period = duration_flag("--period", c.period, true);
  pairing_options.expected_offset = duration_flag("--expected-offset", c.expected_offset, true);
  store::Options read;
  read.read_only = true;

  if (c.inputs.size() == 2) {
    const auto sa = store::Store::open(c.inputs[0], read);
    const auto sb = store::Store::open(c.inputs[1], read);
    const auto a = load_board(sa, only_node(sa, c.channel, c.a_node), c);
    const auto b = load_board(sb, only_node(sb, c.channel, c.b_node), c);
    auto r = selftest::synctest_from_edges(a.t_ns, b.t_ns, a.clock, b.clock, pairing_options, options,
                                           c.growth_ppm);
    r.source = fmt::format("A = {}, B = {}", a.label, b.label);
    return r;
  }
  if (c.inputs.size() != 1)
    throw core::Error(core::ErrorKind::usage,
                      "synctest: give one store (both boards), two stores, or one file");
  const auto& path = c.inputs[0];
  if (!std::filesystem::exists(path))
    throw core::Error(core::ErrorKind::no_input, fmt::format("{}: no such file", path));
  if (is_sqlite_file(path)) {
    const auto store = store::Store::open(path, read);
    std::string a_node = c.a_node, b_node = c.b_node;
    if (a_node.empty() || b_node.empty()) {
      auto nodes = pulse_nodes(store, c.channel);
      if (!a_node.empty()) nodes.erase(a_node);
      if (!b_node.empty()) nodes.erase(b_node);
      const std::size_t missing = (a_node.empty() ? 1u : 0u) + (b_node.empty() ? 1u : 0u);
      if (nodes.size() != missing)
        throw core::Error(
            core::ErrorKind::usage,
            fmt::format("{}: cannot tell the two boards apart on channel '{}' ({} candidate nodes): "
                        "give --a and --b",
                        path, c.channel, nodes.size()));
      auto it = nodes.begin();
      if (a_node.empty()) a_node = *it++;
      if (b_node.empty()) b_node = *it;
    }
    const auto a = load_board(store, a_node, c);
    const auto b = load_board(store, b_node, c);
    auto r = selftest::synctest_from_edges(a.t_ns, b.t_ns, a.clock, b.clock, pairing_options, options,
                                           c.growth_ppm);
    r.source = fmt::format("A = {}, B = {}", a.label, b.label);
    return r;
  }
  auto file = formats::import_file(path, std::nullopt, {});
  if (const auto* sync = std::get_if<formats::SyncImport>(&file.content)) {
    auto r = selftest::synctest_from_rig(*sync, options);
    r.source = fmt::format("{} (the reference rig's offsets, at its trigger times)", path);
    return r;
  }
  const auto* events = std::get_if<formats::EventImport>(&file.content);
  if (!events)
    throw core::Error(core::ErrorKind::data,
                      fmt::format("{}: neither a sync-test CSV nor an events file", path));
  if (c.a_node.empty() || c.b_node.empty())
    throw core::Error(core::ErrorKind::usage, "synctest on an events file: give --a and --b (the two nodes)");
  const auto edge = edge_filter(c.edge);
  std::vector<std::int64_t> a, b;
  for (const auto& e : events->events) {
    if (e.channel != c.channel || (edge && e.edge != *edge) || e.time.clock() != core::Clock::realtime)
      continue;
    if (e.node == c.a_node) a.push_back(e.time.ns());
    if (e.node == c.b_node) b.push_back(e.time.ns());
  }
  auto r = selftest::synctest_from_edges(a, b, {}, {}, pairing_options, options, c.growth_ppm);
  r.source = fmt::format("{}: A = {}/{}, B = {}/{}", path, c.a_node, c.channel, c.b_node, c.channel);
  return r;
}

std::string us(double ns) { return std::isnan(ns) ? "-" : fmt::format("{:.1f}", ns / 1e3); }

std::string text(const selftest::SyncTestResult& r) {
  std::string out =
      fmt::format("synchronisation test: {}\n{} pulses paired", core::printable(r.source), r.series.size());
  if (r.period.count() > 0)
    out += fmt::format(" (period {}; {} on A only, {} on B only)", core::format_duration(r.period),
                       r.unmatched_a, r.unmatched_b);
  out += fmt::format(", tau0 {}, {} gaps\n\n", core::format_duration(r.tau0), r.gaps);
  report::Table table({"offset (us)", "n", "mean", "sd", "min", "P5", "median", "P95", "max"});
  auto pct = [](const selftest::ValueStats& s, double p) {
    for (const auto& [percent, value] : s.percentiles)
      if (percent == p) return value;
    return std::numeric_limits<double>::quiet_NaN();
  };
  auto row = [&](const std::string& name, const selftest::ValueStats& s) {
    table.add_row({name, std::to_string(s.n), us(s.mean_ns), us(s.sd_ns), us(s.min_ns), us(pct(s, 5)),
                   us(pct(s, 50)), us(pct(s, 95)), us(s.max_ns)});
  };
  row("t_B - t_A", r.offset);
  row("|t_B - t_A|", r.abs_offset);
  row("jitter", r.jitter);
  row("|jitter|", r.abs_jitter);
  if (r.daemon_samples > 0) row("measured - daemon", r.daemon_error);
  out += table.render();
  if (r.daemon_samples > 0)
    out +=
        fmt::format("daemons' bound held for {} of {} pulses ({})\n", r.within_daemon_bound, r.daemon_samples,
                    report::percent_text(static_cast<double>(r.within_daemon_bound) /
                                         static_cast<double>(r.daemon_samples)));
  report::Table st({"tau (s)", "ADEV", "MDEV", "TDEV (us)", "MTIE (us)"});
  auto sci = [](double v) { return std::isnan(v) ? std::string("-") : fmt::format("{:.3e}", v); };
  for (const auto& p : r.stability)
    st.add_row({fmt::format("{:.3f}", p.tau_s), sci(p.adev), sci(p.mdev), us(p.tdev_ns), us(p.mtie_ns)});
  out += "\n" + st.render();
  return out;
}

// The offset over time as a standalone SVG file (styles inline, so it displays on its own).
std::string svg(const selftest::SyncTestResult& r) {
  std::vector<double> xs, ys;
  for (const auto& s : r.series) {
    xs.push_back(static_cast<double>(s.t_ns - r.series.front().t_ns) / 1e9);
    ys.push_back(static_cast<double>(s.offset_ns) / 1e6);
  }
  double lo = 0, hi = 1, y_lo = -0.001, y_hi = 0.001;
  if (!xs.empty()) {
    hi = std::max(xs.back(), 1e-9);
    y_lo = *std::min_element(ys.begin(), ys.end());
    y_hi = *std::max_element(ys.begin(), ys.end());
    if (y_hi <= y_lo) y_lo -= 0.001, y_hi += 0.001;
  }
  report::SvgPlot plot("sync-offset", "Clock offset between the boards (t_B - t_A)",
                       "time since the first pulse (s)", "offset (ms)", lo, hi, y_lo, y_hi);
  plot.polyline(xs, ys, report::palette(0));
  plot.note(r.source);
  auto body = plot.render();
  const auto open_end = body.find('>');
  if (open_end != std::string::npos)
    body.insert(open_end + 1,
                "<style>polyline{fill:none;stroke-width:1}text{font:11px sans-serif}line{stroke:#ccc}"
                "</style>");
  return body;
}

}  // namespace

Runner attach_synctest(CLI::App& sub) {
  auto c = std::make_shared<SynctestCommand>();
  sub.add_option("inputs", c->inputs,
                 "Two stores (board A, board B), one store with both, an events file, or the rig's sync CSV")
      ->required();
  sub.add_option("--a", c->a_node, "Node of board A (default: the store's only node with the channel)");
  sub.add_option("--b", c->b_node, "Node of board B");
  sub.add_option("--channel", c->channel, "The channel both boards recorded the pulse on")
      ->capture_default_str();
  sub.add_option("--edge", c->edge, "Edges to pair: both, rising or falling")->capture_default_str();
  sub.add_option("--period", c->period, "Pulse period between paired edges (default: estimated)");
  sub.add_option("--expected-offset", c->expected_offset,
                 "Expected t_B - t_A, when the clocks may be half a period apart or more");
  sub.add_option("--tau0", c->tau0, "Sample interval of ADEV/MDEV/TDEV/MTIE (default: median pulse spacing)");
  sub.add_option("--growth-ppm", c->growth_ppm, "Growth of a clock sample's bound with its distance, ppm")
      ->capture_default_str();
  sub.add_flag("--json", c->json, "Print m2mlat-synctest/1 JSON");
  sub.add_flag("--series", c->series, "With --json: include the offset of every pulse");
  sub.add_option("--csv", c->csv_out, "Write the offset over time as CSV ('-' = stdout)");
  sub.add_option("--svg", c->svg_out, "Write the offset over time as an SVG plot");
  return [c] {
    const auto r = run(*c);
    if (!c->csv_out.empty())
      core::write_output_file(c->csv_out,
                                     [&](std::ostream& out) { selftest::write_series_csv(out, r); });
    if (!c->svg_out.empty())
      core::write_output_file(c->svg_out, [&](std::ostream& out) { out << svg(r); });
    if (c->json)
      print_json(selftest::synctest_json(r, c->series));
    else if (c->csv_out != "-")
      fmt::print("{}", text(r));
    return 0;
  };
}

}  // namespace m2mlat::cli
