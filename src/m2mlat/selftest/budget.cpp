// Error budget arithmetic (terms in budget.hpp).
#include "m2mlat/selftest/budget.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "m2mlat/core/error.hpp"
#include "m2mlat/stats/quantile.hpp"

namespace m2mlat::selftest {

Budget make_budget(std::vector<BudgetTerm> terms) {
  Budget b;
  double squares = 0;
  for (const auto& t : terms) {
    if (t.value_ns < 0 || t.u_ns < 0)
      throw core::Error(core::ErrorKind::usage, fmt::format("error budget: term '{}' is negative", t.name));
    b.total_ns += t.value_ns;
    squares += t.u_ns * t.u_ns;
  }
  b.u_ns = std::sqrt(squares);
  b.terms = std::move(terms);
  return b;
}

BudgetTerm bound_term(std::string name, std::int64_t bound_ns, std::string source) {
  return {std::move(name), bound_ns, std::move(source), static_cast<double>(bound_ns) / std::sqrt(3.0)};
}

BudgetTerm kernel_term(core::Duration worst_a, core::Duration worst_b, std::string source) {
  if (worst_a.count() < 0 || worst_b.count() < 0)
    throw core::Error(core::ErrorKind::usage, "error budget: scheduling latencies must not be negative");
  const double a = static_cast<double>(worst_a.count()), b = static_cast<double>(worst_b.count());
  return {"kernel", std::max(worst_a, worst_b).count(), std::move(source), std::sqrt((a * a + b * b) / 12.0)};
}

BudgetTerm calibration_term(double misalignment_deg, double rate_deg_s, std::string source) {
  if (!(rate_deg_s > 0))
    throw core::Error(core::ErrorKind::usage, "error budget: the steering rate must be positive (deg/s)");
  if (!(misalignment_deg >= 0))
    throw core::Error(core::ErrorKind::usage, "error budget: the misalignment must not be negative (deg)");
  return bound_term("calibration", std::llround(misalignment_deg / rate_deg_s * 1e9), std::move(source));
}

std::optional<RateEstimate> steering_rate(std::span<const std::int64_t> edges_ns, double magnet_angle_deg,
                                          core::Duration max_gap, core::Duration min_gap) {
  if (!(magnet_angle_deg > 0))
    throw core::Error(core::ErrorKind::usage,
                      "error budget: the angle between magnets must be positive (deg)");
  std::vector<double> rates;
  for (std::size_t i = 1; i < edges_ns.size(); ++i) {
    const std::int64_t dt = edges_ns[i] - edges_ns[i - 1];
    if (dt < min_gap.count() || dt > max_gap.count() || dt <= 0) continue;
    rates.push_back(magnet_angle_deg / (static_cast<double>(dt) * 1e-9));
  }
  if (rates.empty()) return std::nullopt;
  std::sort(rates.begin(), rates.end());
  return RateEstimate{stats::quantile(std::span<const double>(rates), 0.5),
                      stats::quantile(std::span<const double>(rates), 0.05), rates.size()};
}

BudgetTerm sync_term_from_synctest(const nlohmann::json& doc, const std::string& statistic,
                                   const std::string& name) {
  auto fail = [&](const std::string& what) { core::throw_data_error({name, 0}, what); };
  if (!doc.is_object() || doc.value("format", "") != "m2mlat-synctest/1")
    fail("not an m2mlat-synctest/1 document (write one with `m2mlat synctest --json`)");
  const auto abs = doc.find("abs_offset");
  if (abs == doc.end() || !abs->is_object()) fail("field 'abs_offset' missing");
  double value = 0;
  std::string what;
  if (statistic == "mean_abs") {
    if (!abs->contains("mean_ns") || !(*abs)["mean_ns"].is_number())
      fail("field 'abs_offset.mean_ns' missing");
    value = (*abs)["mean_ns"].get<double>();
    what = "mean |offset|";
  } else if (statistic == "max_abs") {
    if (!abs->contains("max_ns") || !(*abs)["max_ns"].is_number()) fail("field 'abs_offset.max_ns' missing");
    value = (*abs)["max_ns"].get<double>();
    what = "max |offset|";
  } else if (statistic == "p95_abs") {
    bool found = false;
    for (const auto& p : abs->value("percentiles", nlohmann::json::array()))
      if (p.value("percent", -1.0) == 95.0 && p["ns"].is_number()) {
        value = p["ns"].get<double>();
        found = true;
      }
    if (!found) fail("no 95th percentile in 'abs_offset.percentiles'");
    what = "P95 |offset|";
  } else {
    throw core::Error(core::ErrorKind::usage,
                      fmt::format("unknown sync statistic '{}' (mean_abs, p95_abs or max_abs)", statistic));
  }
  // u: the offsets' RMS about zero, from their mean and sd.
  const auto offset = doc.find("offset");
  const auto number_at = [&](const char* key) {
    if (offset == doc.end() || !offset->is_object() || !offset->contains(key) || !offset->at(key).is_number())
      fail(fmt::format("field 'offset.{}' missing", key));
    return offset->at(key).get<double>();
  };
  const double mean = number_at("mean_ns"), sd = number_at("sd_ns");
  return {"sync", std::llround(value), fmt::format("synctest {}: {}", name, what), std::sqrt(mean * mean + sd * sd)};
}

BudgetTerm onset_term_from_onsettest(const nlohmann::json& doc, const std::string& detector,
                                     const std::string& speed, const std::string& name) {
  auto fail = [&](const std::string& what) { core::throw_data_error({name, 0}, what); };
  if (!doc.is_object() || doc.value("format", "") != "m2mlat-onsettest/1")
    fail("not an m2mlat-onsettest/1 document (write one with `m2mlat onsettest --json`)");
  const auto rows = doc.find("onset");
  if (rows == doc.end() || !rows->is_array()) fail("field 'onset' missing");
  // Per speed class: |p95| of the hand + |p95| of the actuator, ns.
  std::vector<std::pair<std::string, std::pair<double, double>>> classes;  // name, (worst, u)
  for (const auto& cls : doc.value("speed_classes", nlohmann::json::array())) {
    const auto cls_name = cls.value("name", std::string());
    if (speed != "worst" && cls_name != speed) continue;
    double sum = 0, squares = 0;
    for (const char* profile : {"hand", "actuator"}) {
      const nlohmann::json* row = nullptr;
      for (const auto& r : *rows)
        if (r.value("detector", "") == detector && r.value("profile", "") == profile &&
            r.value("speed", "") == cls_name)
          row = &r;
      if (row == nullptr)
        fail(fmt::format("no '{}' row of detector '{}' in speed class '{}'", profile, detector, cls_name));
      const auto& e = (*row).value("onset_error", nlohmann::json::object());
      if (!e.contains("abs_p95_ns") || !e["abs_p95_ns"].is_number())
        fail(fmt::format("field 'onset_error.abs_p95_ns' missing ({} {} {})", detector, profile, cls_name));
      const double p95 = e["abs_p95_ns"].get<double>();
      sum += p95;
      squares += p95 * p95;
    }
    classes.emplace_back(cls_name, std::pair{sum, std::sqrt(squares) / 1.96});
  }
  if (classes.empty()) {
    if (speed != "worst" && speed != "slow" && speed != "medium" && speed != "fast")
      throw core::Error(core::ErrorKind::usage,
                        fmt::format("unknown onset speed '{}' (slow, medium, fast or worst)", speed));
    fail(speed == "worst" ? std::string("field 'speed_classes' missing or empty")
                          : fmt::format("no speed class '{}' in 'speed_classes'", speed));
  }
  const auto worst = std::max_element(classes.begin(), classes.end(),
                                      [](const auto& a, const auto& b) { return a.second.first < b.second.first; });
  return {"onset", std::llround(worst->second.first),
          fmt::format("onsettest {}: {} |p95| hand + actuator, {} motions", name, detector, worst->first),
          worst->second.second};
}

nlohmann::json budget_json(const Budget& budget) {
  nlohmann::json j{{"format", kBudgetFormat}, {"terms", nlohmann::json::array()}};
  for (const auto& t : budget.terms)
    j["terms"].push_back({{"name", t.name},
                          {"ns", t.value_ns},
                          {"ms", static_cast<double>(t.value_ns) / 1e6},
                          {"u_ns", t.u_ns},
                          {"u_ms", t.u_ns / 1e6},
                          {"source", t.source}});
  j["total_ns"] = budget.total_ns;
  j["total_ms"] = static_cast<double>(budget.total_ns) / 1e6;
  j["u_ns"] = budget.u_ns;
  j["u_ms"] = budget.u_ns / 1e6;
  j["U95_ns"] = budget.expanded_ns();
  j["U95_ms"] = budget.expanded_ns() / 1e6;
  return j;
}

}  // namespace m2mlat::selftest
