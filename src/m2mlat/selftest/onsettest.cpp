// The onset test (definitions in onsettest.hpp).
#include "m2mlat/selftest/onsettest.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>

#include "m2mlat/core/error.hpp"
#include "m2mlat/formats/json_number.hpp"
#include "m2mlat/onset/detectors.hpp"
#include "m2mlat/sim/random.hpp"
#include "m2mlat/stats/quantile.hpp"

namespace m2mlat::selftest {

namespace {

constexpr double kUndefined = std::numeric_limits<double>::quiet_NaN();  // a figure of no sample
using formats::number;
constexpr std::int64_t kMs = 1'000'000;
constexpr std::uint64_t kPlanStream = 0x6f6e'7365;  // "onse": the motions' parameters

// One motion's traces: the operator's chip (A), a second chip on the same body (B, the baseline) and
// the vehicle's chip; each with its true motion.
struct Trial {
  sim::RateMotion hand, vehicle;
  core::RateTrace operator_a, operator_b, vehicle_trace;
};

Trial make_trial(const OnsetTestOptions& o, std::size_t speed, int index, sim::Rng& plan) {
  const auto& cls = kSpeedClasses[speed];
  const std::int64_t rest = 300 * kMs + plan.uniform_int(0, 300 * kMs);
  const double peak = plan.uniform(cls.min_deg_s, cls.max_deg_s);
  const std::int64_t duration = 400 * kMs + plan.uniform_int(0, 800 * kMs);
  const int direction = plan.bernoulli(0.5) ? 1 : -1;
  const std::int64_t delay = 50 * kMs + plan.uniform_int(0, 100 * kMs);
  Trial t;
  t.hand = sim::hand_motion(rest, peak, duration, direction, o.hand_shape);
  t.vehicle = sim::actuator_motion(t.hand, delay, o.actuator);
  const auto chip = static_cast<std::uint64_t>(speed) * 1'000'000 + static_cast<std::uint64_t>(index) * 3;
  const std::span<const sim::RateMotion> hand(&t.hand, 1), vehicle(&t.vehicle, 1);
  t.operator_a = sim::simulate_gyro(o.gyro, hand, 0, t.hand.end_ns() + 300 * kMs, o.seed, chip);
  t.operator_b = sim::simulate_gyro(o.gyro, hand, 0, t.hand.end_ns() + 300 * kMs, o.seed, chip + 1);
  t.vehicle_trace = sim::simulate_gyro(o.gyro, vehicle, 0, t.vehicle.end_ns() + 300 * kMs, o.seed, chip + 2);
  return t;
}

// The detected motion that stands for `truth`: the one whose onset is nearest the true onset, within
// half the motion's duration before it and its end after it. Null when there is none.
const onset::Motion* match(const onset::Detection& d, const sim::RateMotion& truth) {
  const onset::Motion* best = nullptr;
  for (const auto& m : d.motions) {
    if (m.onset_ns < truth.onset_ns - truth.duration_ns / 2 || m.onset_ns > truth.end_ns()) continue;
    if (!best || std::llabs(m.onset_ns - truth.onset_ns) < std::llabs(best->onset_ns - truth.onset_ns))
      best = &m;
  }
  return best;
}

struct Tally {
  std::size_t motions = 0, found = 0, extra = 0;
  std::size_t covered = 0;  // |onset error| <= 2 x the stated sd
  std::vector<double> onset, end, stated;
  void add(const onset::Detection& d, const sim::RateMotion& truth) {
    ++motions;
    const auto* m = match(d, truth);
    extra += d.motions.size() - (m ? 1 : 0);
    if (!m) return;
    ++found;
    onset.push_back(static_cast<double>(m->onset_ns - truth.onset_ns));
    stated.push_back(static_cast<double>(m->onset_sd_ns));
    if (std::llabs(m->onset_ns - truth.onset_ns) <= 2 * m->onset_sd_ns) ++covered;
    if (m->ended) end.push_back(static_cast<double>(m->end_ns - truth.end_ns()));
  }
  OnsetRow row(std::string detector, std::string profile, std::string speed) && {
    OnsetRow r{std::move(detector),
               std::move(profile),
               std::move(speed),
               motions,
               found,
               extra,
               error_spread(onset),
               error_spread(end),
               kUndefined,
               found > 0 ? static_cast<double>(covered) / static_cast<double>(found) : kUndefined};
    if (!stated.empty()) {
      std::sort(stated.begin(), stated.end());
      r.median_stated_sd_ns = stats::quantile(std::span<const double>(stated), 0.5);
    }
    return r;
  }
};


nlohmann::json spread_json(const ErrorSpread& s) {
  return {{"n", s.n},
          {"median_ns", number(s.median_ns)},
          {"p5_ns", number(s.p5_ns)},
          {"p95_ns", number(s.p95_ns)},
          {"abs_p95_ns", number(s.abs_p95_ns)}};
}

std::string ms(double ns) { return std::isnan(ns) ? "-" : fmt::format("{:+.3f}", ns / 1e6); }
std::string range(const ErrorSpread& s) {
  return s.n == 0 ? "-" : fmt::format("{}..{}", ms(s.p5_ns), ms(s.p95_ns));
}

}  // namespace

ErrorSpread error_spread(std::vector<double> errors_ns) {
  ErrorSpread s;
  s.n = errors_ns.size();
  if (errors_ns.empty()) {
    s.median_ns = s.p5_ns = s.p95_ns = s.abs_p95_ns = kUndefined;
    return s;
  }
  std::sort(errors_ns.begin(), errors_ns.end());
  const std::span<const double> sorted(errors_ns);
  s.median_ns = stats::quantile(sorted, 0.5);
  s.p5_ns = stats::quantile(sorted, 0.05);
  s.p95_ns = stats::quantile(sorted, 0.95);
  for (auto& e : errors_ns) e = std::fabs(e);
  std::sort(errors_ns.begin(), errors_ns.end());
  s.abs_p95_ns = stats::quantile(std::span<const double>(errors_ns), 0.95);
  return s;
}

OnsetTestResult run_onsettest(const OnsetTestOptions& options) {
  if (options.motions < 1)
    throw core::Error(core::ErrorKind::usage,
                      fmt::format("onset test: {} motions per class (at least 1)", options.motions));
  std::vector<const onset::Detector*> detectors;
  for (const auto& name : options.detectors) detectors.push_back(&onset::detector(name));
  sim::check(options.gyro);

  OnsetTestResult result;
  result.options = options;
  std::vector<double> seconds(detectors.size(), 0.0);
  for (std::size_t speed = 0; speed < kSpeedClasses.size(); ++speed) {
    std::vector<Tally> hand(detectors.size()), vehicle(detectors.size());
    std::vector<std::vector<double>> m2m(detectors.size());
    sim::Rng plan(options.seed, kPlanStream + speed);
    for (int i = 0; i < options.motions; ++i) {
      const auto trial = make_trial(options, speed, i, plan);
      result.samples += trial.operator_a.samples.size() + trial.operator_b.samples.size() +
                        trial.vehicle_trace.samples.size();
      for (std::size_t d = 0; d < detectors.size(); ++d) {
        const auto start = std::chrono::steady_clock::now();
        const auto a = detectors[d]->detect(trial.operator_a);
        const auto b = detectors[d]->detect(trial.operator_b);
        const auto v = detectors[d]->detect(trial.vehicle_trace);
        seconds[d] += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        hand[d].add(a, trial.hand);
        vehicle[d].add(v, trial.vehicle);
        const auto* ma = match(a, trial.hand);
        const auto* mb = match(b, trial.hand);
        if (ma && mb) m2m[d].push_back(static_cast<double>(mb->onset_ns - ma->onset_ns));
      }
    }
    const std::string speed_name(kSpeedClasses[speed].name);
    for (std::size_t d = 0; d < detectors.size(); ++d) {
      const std::string name(detectors[d]->name);
      result.rows.push_back(std::move(hand[d]).row(name, "hand", speed_name));
      result.rows.push_back(std::move(vehicle[d]).row(name, "actuator", speed_name));
      result.baseline.push_back({name, speed_name, m2m[d].size(), error_spread(m2m[d])});
    }
  }
  for (std::size_t d = 0; d < detectors.size(); ++d)
    result.samples_per_s.emplace_back(
        std::string(detectors[d]->name),
        seconds[d] > 0 ? static_cast<double>(result.samples) / seconds[d] : kUndefined);
  // Rows grouped by detector, then profile, then speed.
  std::stable_sort(result.rows.begin(), result.rows.end(), [](const OnsetRow& x, const OnsetRow& y) {
    return std::tie(x.detector, x.profile) < std::tie(y.detector, y.profile);
  });
  std::stable_sort(result.baseline.begin(), result.baseline.end(),
                   [](const BaselineRow& x, const BaselineRow& y) { return x.detector < y.detector; });
  return result;
}

nlohmann::json onsettest_json(const OnsetTestResult& r) {
  nlohmann::json j{{"format", "m2mlat-onsettest/1"},
                   {"seed", r.options.seed},
                   {"motions_per_class", r.options.motions},
                   {"hand_shape", sim::hand_shape_name(r.options.hand_shape)},
                   {"samples", r.samples},
                   {"gyro",
                    {{"noise_sd_deg_s", r.options.gyro.noise_sd_deg_s()},
                     {"bias_sd_deg_s", r.options.gyro.bias_sd_deg_s},
                     {"period_ns", r.options.gyro.period_ns},
                     {"read_ns", r.options.gyro.read_ns},
                     {"jitter_ns", r.options.gyro.jitter_ns}}}};
  auto& classes = j["speed_classes"] = nlohmann::json::array();
  for (const auto& c : kSpeedClasses)
    classes.push_back({{"name", c.name}, {"min_deg_s", c.min_deg_s}, {"max_deg_s", c.max_deg_s}});
  auto& rows = j["onset"] = nlohmann::json::array();
  for (const auto& row : r.rows)
    rows.push_back({{"detector", row.detector},
                    {"profile", row.profile},
                    {"speed", row.speed},
                    {"motions", row.motions},
                    {"found", row.found},
                    {"extra", row.extra},
                    {"onset_error", spread_json(row.onset)},
                    {"end_error", spread_json(row.end)},
                    {"median_stated_sd_ns", number(row.median_stated_sd_ns)},
                    {"within_2sd_share", number(row.within_2sd_share)}});
  auto& base = j["baseline"] = nlohmann::json::array();
  for (const auto& b : r.baseline)
    base.push_back(
        {{"detector", b.detector}, {"speed", b.speed}, {"pairs", b.pairs}, {"m2m", spread_json(b.m2m)}});
  auto& speed = j["samples_per_s"] = nlohmann::json::object();
  for (const auto& [name, rate] : r.samples_per_s) speed[name] = number(rate);
  return j;
}

std::string onsettest_text(const OnsetTestResult& r) {
  std::string out = fmt::format(
      "onset test: seed {}, {} motions per speed class ({} hand), {} samples; gyro noise {:.3f} deg/s rms, {} kHz\n"
      "errors are detected - true, ms (positive: late); |p95| = 95th percentile of |error|;\n"
      "sd med = the detector's stated onset sd (median); <=2sd = share of onsets within 2 stated sd\n\n",
      r.options.seed, r.options.motions, sim::hand_shape_name(r.options.hand_shape), r.samples,
      r.options.gyro.noise_sd_deg_s(),
      1e6 / static_cast<double>(r.options.gyro.period_ns));
  out += fmt::format("{:<10} {:<9} {:<7} {:>8} {:>6} {:>9} {:>17} {:>8} {:>9} {:>17} {:>8} {:>8} {:>6}\n",
                     "detector", "profile", "speed", "found", "extra", "onset med", "onset p5..p95", "|p95|",
                     "end med", "end p5..p95", "|p95|", "sd med", "<=2sd");
  for (const auto& row : r.rows)
    out += fmt::format("{:<10} {:<9} {:<7} {:>8} {:>6} {:>9} {:>17} {:>8} {:>9} {:>17} {:>8} {:>8} {:>6}\n",
                       row.detector, row.profile, row.speed, fmt::format("{}/{}", row.found, row.motions),
                       row.extra, ms(row.onset.median_ns), range(row.onset), ms(row.onset.abs_p95_ns),
                       ms(row.end.median_ns), range(row.end), ms(row.end.abs_p95_ns),
                       ms(row.median_stated_sd_ns),
                       std::isnan(row.within_2sd_share) ? std::string("-")
                                                        : fmt::format("{:.0f}%", 100 * row.within_2sd_share));
  out += fmt::format(
      "\nbaseline (two chips on one body, true M2M = 0), ms\n{:<10} {:<7} {:>6} {:>9} {:>17} {:>8}\n",
      "detector", "speed", "pairs", "median", "p5..p95", "|p95|");
  for (const auto& b : r.baseline)
    out += fmt::format("{:<10} {:<7} {:>6} {:>9} {:>17} {:>8}\n", b.detector, b.speed, b.pairs,
                       ms(b.m2m.median_ns), range(b.m2m), ms(b.m2m.abs_p95_ns));
  out += "\nthroughput on this machine:";
  for (const auto& [name, rate] : r.samples_per_s)
    out += fmt::format(" {} {:.1f} M samples/s;", name, rate / 1e6);
  out += "\n";
  return out;
}

}  // namespace m2mlat::selftest
