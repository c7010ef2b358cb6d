// The name a user most likely meant.
#include "m2mlat/core/nearest.hpp"

#include <gtest/gtest.h>

#include <string>
#include <vector>

namespace m2mlat::core {

TEST(Nearest, ASlipOrAnotherCaseIsFoundAndAFarWordIsNot) {
  const std::vector<std::string> commands{"stats", "pair", "simulate", "import", "export", "report"};
  EXPECT_EQ(nearest("stat", commands), "stats");       // a prefix
  EXPECT_EQ(nearest("simulat", commands), "simulate");
  EXPECT_EQ(nearest("improt", commands), "import");    // two letters swapped: 2 edits of 6
  EXPECT_EQ(nearest("STATS", commands), "stats");      // letter case
  EXPECT_FALSE(nearest("stats", commands));            // itself
  EXPECT_FALSE(nearest("xyz", commands));
  EXPECT_FALSE(nearest("", commands));
  const std::vector<std::string> scenarios{"static_5g", "static_wifi"};
  EXPECT_EQ(nearest("static_5G", scenarios), "static_5g");
  EXPECT_EQ(did_you_mean("static_5G", scenarios), " (did you mean 'static_5g'?)");
  EXPECT_EQ(did_you_mean("urban", scenarios), "");
}

}  // namespace m2mlat::core
