// Scenario colours: from the name, distinct within a report, and the same whatever else it holds.
#include "m2mlat/report/scenario_colours.hpp"

#include <gtest/gtest.h>

#include <set>
#include <string>
#include <vector>

using m2mlat::report::scenario_colours;

TEST(ScenarioColours, ANameKeepsItsColourWhateverTheOtherScenariosAndTheirOrder) {
  const std::vector<std::string> study{"static_wifi", "static_5g", "dynamic_co_referenced", "dynamic_autonomous"};
  const auto colours = scenario_colours(study);
  EXPECT_EQ(std::set<std::size_t>(colours.begin(), colours.end()).size(), 4u);  // the study's four apart
  for (std::size_t i = 0; i < study.size(); ++i) {
    EXPECT_EQ(scenario_colours(std::vector<std::string>{study[i]}).front(), colours[i]) << study[i];
    const std::vector<std::string> reversed(study.rbegin(), study.rend());
    EXPECT_EQ(scenario_colours(reversed)[study.size() - 1 - i], colours[i]) << study[i];
  }
  // Eight names take the eight colours; a ninth shares.
  std::vector<std::string> many;
  for (int k = 0; k < 9; ++k) many.push_back("run-" + std::to_string(k));
  const auto eight = scenario_colours(many);
  EXPECT_EQ(std::set<std::size_t>(eight.begin(), eight.begin() + 8).size(), 8u);
  for (const auto c : eight) EXPECT_LT(c, 8u);
}
