// The error budget's onset term of an inertial source, from the onset test's measurement.
#include <gtest/gtest.h>

#include <cmath>

#include "m2mlat/core/error.hpp"
#include "m2mlat/selftest/budget.hpp"
#include "m2mlat/selftest/onsettest.hpp"

namespace m2mlat::selftest::budget_onset_test {

namespace {

const nlohmann::json& measured() {
  static const nlohmann::json doc = [] {
    OnsetTestOptions o;
    o.motions = 6;
    o.detectors = {"flank"};
    return onsettest_json(run_onsettest(o));
  }();
  return doc;
}

double abs_p95(const nlohmann::json& doc, const std::string& profile, const std::string& speed) {
  for (const auto& r : doc["onset"])
    if (r["detector"] == "flank" && r["profile"] == profile && r["speed"] == speed)
      return r["onset_error"]["abs_p95_ns"].get<double>();
  ADD_FAILURE() << "no row " << profile << " " << speed;
  return 0;
}

TEST(BudgetOnset, HandPlusActuatorOfTheWorstClass) {
  const auto& doc = measured();
  double worst = 0;
  for (const char* speed : {"slow", "medium", "fast"}) {
    const double sum = abs_p95(doc, "hand", speed) + abs_p95(doc, "actuator", speed);
    const auto term = onset_term_from_onsettest(doc, "flank", speed, "t.json");
    EXPECT_EQ(term.name, "onset");
    EXPECT_EQ(term.value_ns, std::llround(sum)) << speed;
    worst = std::max(worst, sum);
  }
  const auto term = onset_term_from_onsettest(doc, "flank", "worst", "t.json");
  EXPECT_EQ(term.value_ns, std::llround(worst));
  EXPECT_NE(term.source.find("t.json"), std::string::npos);
  // It takes the magnet's place in the budget: 10 ms of calibration there, the measured term here.
  const auto budget = make_budget({{"sync", 100'000, "given"}, term});
  EXPECT_EQ(budget.total_ns, 100'000 + term.value_ns);
  EXPECT_LT(term.value_ns, 10'000'000);
}

TEST(BudgetOnset, MissingPartsNamed) {
  const auto& doc = measured();
  const auto message = [&](const nlohmann::json& d, const std::string& detector, const std::string& speed) {
    try {
      onset_term_from_onsettest(d, detector, speed, "t.json");
    } catch (const core::Error& e) {
      return std::string(e.what());
    }
    return std::string("accepted");
  };
  EXPECT_NE(message(doc, "reference", "worst").find("detector 'reference'"), std::string::npos);
  EXPECT_NE(message(nlohmann::json{{"format", "m2mlat-synctest/1"}}, "flank", "worst").find("t.json"),
            std::string::npos);
  EXPECT_NE(message(doc, "flank", "quick").find("unknown onset speed 'quick'"), std::string::npos);
  auto cut = doc;
  cut["onset"][0]["onset_error"].erase("abs_p95_ns");
  EXPECT_NE(message(cut, "flank", "worst").find("abs_p95_ns"), std::string::npos);
}

}  // namespace

}  // namespace m2mlat::selftest::budget_onset_test
