// `m2mlat budget`: the measurement's error budget, term by term (selftest/budget.hpp).
#include <fmt/format.h>

#include <algorithm>
#include <fstream>
#include <limits>
#include <map>
#include <memory>

#include "m2mlat/cli/command.hpp"
#include "m2mlat/cli/duration_flag.hpp"
#include "m2mlat/cli/output.hpp"
#include "m2mlat/core/error.hpp"
#include "m2mlat/report/table.hpp"
#include "m2mlat/selftest/budget.hpp"
#include "m2mlat/selftest/onsettest.hpp"
#include "m2mlat/stats/quantile.hpp"
#include "m2mlat/store/store.hpp"

namespace m2mlat::cli {

namespace {

struct BudgetCommand {
  std::string sync;      // a given value, e.g. "0.3ms"
  std::string synctest;  // a synctest JSON file
  std::string sync_stat = "mean_abs";
  std::string sync_store;                  // live clock bounds
  std::string kernel_a = "0us", kernel_b;  // worst scheduling latency of each board
  std::string circuit = "2us";
  double misalignment_deg = 1.0;
  double rate_deg_s = 0;  // 0: measured from --rate-store
  std::string rate_store, rate_channel;
  double magnet_angle_deg = 0;
  std::string rate_stat = "median";
  std::string rate_min_gap = "5ms", rate_max_gap = "1s";
  std::string source = "hall";  // hall: E_calib; inertial: the measured onset term E_onset
  std::string onsettest;        // an m2mlat-onsettest/1 file; empty: run the onset test here
  std::string onset_detector = "flank";
  std::string onset_speed = "worst";
  int onset_motions = 30;  // per speed class, when the test runs here
  bool json = false;
};

store::Store open_read_only(const std::string& path) {
  store::Options read;
  read.read_only = true;
  return store::Store::open(path, read);
}

// E_sync from the daemons' own bounds: the median max_error of each of the two nodes with clock
// samples, added; its u the root sum of squares of their median est_error.
selftest::BudgetTerm sync_from_store(const std::string& path) {
  const auto store = open_read_only(path);
  std::map<std::string, std::vector<std::int64_t>> bounds, estimates;
  for (const auto& s : store.sessions())
    for (const auto& cs : store.clock_samples(s.id))
      if (cs.source != "step" && cs.synchronised && cs.max_error_ns >= 0) {
        bounds[s.node].push_back(cs.max_error_ns);
        estimates[s.node].push_back(std::max<std::int64_t>(0, cs.est_error_ns));
      }
  if (bounds.size() != 2)
    throw core::Error(core::ErrorKind::data,
                      fmt::format("{}: {} nodes have synchronised clock samples; the sync term needs two",
                                  path, bounds.size()));
  std::int64_t total = 0;
  double squares = 0;
  std::string nodes;
  for (auto& [node, values] : bounds) {
    std::sort(values.begin(), values.end());
    total += std::llround(stats::quantile(std::span<const std::int64_t>(values), 0.5));
    const double u = stats::median(estimates[node]);
    squares += u * u;
    nodes += (nodes.empty() ? "" : " + ") + node;
  }
  return {"sync", total, fmt::format("{}: median daemon max_error of {} (u: their est_error)", path, nodes),
          std::sqrt(squares)};
}

selftest::BudgetTerm sync_term(const BudgetCommand& c) {
  const int given = !c.sync.empty() + !c.synctest.empty() + !c.sync_store.empty();
  if (given != 1)
    throw core::Error(core::ErrorKind::usage,
                      "budget: give the sync term once: --sync, --synctest or --sync-store");
  if (!c.sync.empty()) return selftest::bound_term("sync", duration_flag("--sync", c.sync).count(), "given");
  if (!c.sync_store.empty()) return sync_from_store(c.sync_store);
  std::ifstream in(c.synctest);
  if (!in) throw core::Error(core::ErrorKind::no_input, fmt::format("{}: cannot open", c.synctest));
  nlohmann::json doc;
  try {
    doc = nlohmann::json::parse(in);
  } catch (const nlohmann::json::exception& e) {
    core::throw_data_error({c.synctest, 0}, fmt::format("not JSON: {}", e.what()));
  }
  return selftest::sync_term_from_synctest(doc, c.sync_stat, c.synctest);
}

selftest::BudgetTerm calibration(const BudgetCommand& c) {
  if (c.rate_deg_s > 0)
    return selftest::calibration_term(
        c.misalignment_deg, c.rate_deg_s,
        fmt::format("given: {} deg at {} deg/s", c.misalignment_deg, c.rate_deg_s));
  if (c.rate_store.empty() || c.rate_channel.empty() || !(c.magnet_angle_deg > 0))
    throw core::Error(core::ErrorKind::usage,
                      "budget: give --rate (deg/s), or --rate-store with --rate-channel node/channel and "
                      "--magnet-angle (deg between neighbouring magnets)");
  const auto store = open_read_only(c.rate_store);
  const auto ref = core::parse_channel_ref(c.rate_channel, "wheel");
  store::EventFilter filter;
  filter.node = ref.node;
  filter.channel = ref.channel;
  filter.edge = core::Edge::falling;
  const auto ts = store.timestamps(
      core::TimePoint::from_ns(core::Clock::realtime, std::numeric_limits<std::int64_t>::min()),
      core::TimePoint::from_ns(core::Clock::realtime, std::numeric_limits<std::int64_t>::max()), filter);
  const auto rate =
      selftest::steering_rate(ts.t_ns, c.magnet_angle_deg, duration_flag("--rate-max-gap", c.rate_max_gap),
                              duration_flag("--rate-min-gap", c.rate_min_gap));
  if (!rate)
    throw core::Error(
        core::ErrorKind::data,
        fmt::format("{}: no two consecutive edges of {} close enough to measure the steering rate",
                    c.rate_store, c.rate_channel));
  if (c.rate_stat != "median" && c.rate_stat != "p5")
    throw core::Error(core::ErrorKind::usage, "--rate-stat: median or p5");
  const double value = c.rate_stat == "median" ? rate->median_deg_s : rate->p5_deg_s;
  return selftest::calibration_term(
      c.misalignment_deg, value,
      fmt::format("{} deg at {:.1f} deg/s ({} rate of {} intervals of {} in {})", c.misalignment_deg, value,
                  c.rate_stat, rate->intervals, c.rate_channel, c.rate_store));
}

// E_onset of an inertial source: from the onset test's file, or measured here by the same routine.
selftest::BudgetTerm onset(const BudgetCommand& c) {
  if (c.rate_deg_s > 0 || !c.rate_store.empty())
    throw core::Error(
        core::ErrorKind::usage,
        "budget: --rate and --rate-store measure the magnet's calibration term (--source hall); "
        "an inertial source's term is its onset error (--onsettest)");
  nlohmann::json doc;
  std::string name = c.onsettest;
  if (c.onsettest.empty()) {
    selftest::OnsetTestOptions options;
    options.motions = c.onset_motions;
    options.detectors = {c.onset_detector};
    doc = selftest::onsettest_json(selftest::run_onsettest(options));
    name = fmt::format("(run here, seed {})", options.seed);
  } else {
    std::ifstream in(c.onsettest);
    if (!in) throw core::Error(core::ErrorKind::no_input, fmt::format("{}: cannot open", c.onsettest));
    try {
      doc = nlohmann::json::parse(in);
    } catch (const nlohmann::json::exception& e) {
      core::throw_data_error({c.onsettest, 0}, fmt::format("not JSON: {}", e.what()));
    }
  }
  return selftest::onset_term_from_onsettest(doc, c.onset_detector, c.onset_speed, name);
}

selftest::BudgetTerm motion_term(const BudgetCommand& c) {
  if (c.source == "hall") return calibration(c);
  if (c.source == "inertial") return onset(c);
  throw core::Error(core::ErrorKind::usage, fmt::format("--source: hall or inertial, not '{}'", c.source));
}

}  // namespace

Runner attach_budget(CLI::App& sub) {
  auto c = std::make_shared<BudgetCommand>();
  auto* sync = sub.add_option_group("sync", "E_sync: the boards' clock disagreement (one of these)");
  sync->add_option("--sync", c->sync, "A given value, e.g. 0.3ms");
  sync->add_option("--synctest", c->synctest, "A `m2mlat synctest --json` result");
  sync->add_option("--sync-stat", c->sync_stat, "Of the synctest: mean_abs, p95_abs or max_abs")
      ->capture_default_str();
  sync->add_option("--sync-store", c->sync_store,
                   "A store whose two nodes recorded clock samples (their bounds)");
  auto* kernel = sub.add_option_group(
      "kernel", "E_kernel: timestamping asymmetry = max of the two boards' worst latency");
  kernel
      ->add_option("--kernel-a", c->kernel_a, "Board A's worst scheduling latency (cyclictest max), e.g. 5us")
      ->capture_default_str();
  kernel->add_option("--kernel-b", c->kernel_b, "Board B's (default: the same as A)");
  sub.add_option("--circuit", c->circuit, "E_circuit: sensor and input circuit (A3144: about 2 us)")
      ->capture_default_str();
  auto* calib = sub.add_option_group("calibration", "E_calib = misalignment / steering rate");
  calib->add_option("--misalignment", c->misalignment_deg, "Sensor misalignment between the wheels, degrees")
      ->capture_default_str();
  calib->add_option("--rate", c->rate_deg_s, "Steering rate, deg/s");
  calib->add_option("--rate-store", c->rate_store,
                    "Measure the rate in this store (a wheel with several magnets)");
  calib->add_option("--rate-channel", c->rate_channel, "node/channel of that wheel");
  calib->add_option("--magnet-angle", c->magnet_angle_deg, "Angle between neighbouring magnets, degrees");
  calib->add_option("--rate-stat", c->rate_stat, "median, or p5 (a slow manoeuvre)")->capture_default_str();
  calib->add_option("--rate-min-gap", c->rate_min_gap, "Shorter intervals are bounces")
      ->capture_default_str();
  calib->add_option("--rate-max-gap", c->rate_max_gap, "Longer intervals are between manoeuvres")
      ->capture_default_str();
  auto* motion = sub.add_option_group(
      "onset", "E_onset: an inertial source's measured onset error, in place of E_calib (--source inertial)");
  motion->add_option("--source", c->source, "The motion source: hall (E_calib) or inertial (E_onset)")
      ->capture_default_str();
  motion->add_option("--onsettest", c->onsettest,
                     "A `m2mlat onsettest --json` result (default: run the onset test here)");
  motion->add_option("--onset-detector", c->onset_detector, "The onset detector: flank or reference")
      ->capture_default_str();
  motion->add_option("--onset-speed", c->onset_speed, "Speed class: slow, medium, fast or worst")
      ->capture_default_str();
  motion->add_option("--onset-motions", c->onset_motions, "Motions per speed class when the test runs here")
      ->check(CLI::Range(1, 100'000))
      ->capture_default_str();
  sub.add_flag("--json", c->json, "Print m2mlat-budget/1 JSON");
  return [c] {
    const auto ka = duration_flag("--kernel-a", c->kernel_a);
    const auto kb = c->kernel_b.empty() ? ka : duration_flag("--kernel-b", c->kernel_b);
    const auto budget = selftest::make_budget(
        {sync_term(*c),
         selftest::kernel_term(
             ka, kb, fmt::format("max(A {}, B {})", core::format_duration(ka), core::format_duration(kb))),
         selftest::bound_term("circuit", duration_flag("--circuit", c->circuit).count(), "sensor and input circuit"),
         motion_term(*c)});
    if (c->json) {
      print_json(selftest::budget_json(budget));
      return 0;
    }
    report::Table table({"term", "worst (ms)", "u (ms)", "from"});
    const auto ms = [](double ns) { return fmt::format("{:.4f}", ns / 1e6); };
    for (const auto& t : budget.terms)
      table.add_row({t.name, ms(static_cast<double>(t.value_ns)), ms(t.u_ns), t.source});
    table.add_row({"total (sum)", ms(static_cast<double>(budget.total_ns)), ms(budget.u_ns),
                   "worst case: the sum; u: root sum of squares (independent terms)"});
    table.add_row({"U95", "", ms(budget.expanded_ns()), "expanded uncertainty, 2 u (k = 2, about 95 %)"});
    fmt::print("error budget of one latency sample (worst case, and standard uncertainty u, k = 1; "
               "docs/precision.md)\n{}",
               table.render());
    return 0;
  };
}

}  // namespace m2mlat::cli
