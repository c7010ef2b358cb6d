// The stages file: its selectors, and errors naming the file, the line and the field.
#include "m2mlat/analysis/stage_rule.hpp"

#include <gtest/gtest.h>

#include "m2mlat/core/error.hpp"

using namespace m2mlat;
using namespace m2mlat::analysis;

namespace m2mlat::analysis::stage_rule_test {

// The message of the usage error parsing `text` throws (fails the test when none is thrown).
std::string rule_error_of(std::string_view text) {
  try {
    parse_stage_rule(text, "stages.txt");
  } catch (const core::Error& e) {
    EXPECT_EQ(e.kind(), core::ErrorKind::usage);
    return e.what();
  }
  ADD_FAILURE() << "no error for: " << text;
  return {};
}

TEST(StageRule, ParsesEverySelectorInOrder) {
  const auto rule = parse_stage_rule(
      "# where the time goes\n"
      "operator_software = first operator:command after cause\n"
      "\n"
      "send = same key operator:send\n"
      "  network   =   same  key vehicle:receive  \n"
      "vehicle.sw = first vehicle:apply after previous\n"
      "queue-wait = last vehicle:apply before effect\n"
      "actuator = effect\n",
      "stages.txt");
  ASSERT_EQ(rule.stages.size(), 6u);
  EXPECT_EQ(rule.names(), (std::vector<std::string>{"operator_software", "send", "network", "vehicle.sw",
                                                    "queue-wait", "actuator"}));
  EXPECT_EQ(rule.stages[0].end.kind, SelectorKind::first_after_cause);
  EXPECT_EQ(rule.stages[0].end.node, "operator");
  EXPECT_EQ(rule.stages[0].end.name, "command");
  EXPECT_EQ(rule.stages[0].line, 2);
  EXPECT_EQ(rule.stages[2].end.kind, SelectorKind::same_key);
  EXPECT_EQ(rule.stages[2].end.node, "vehicle");
  EXPECT_EQ(rule.stages[2].line, 5);
  EXPECT_EQ(rule.stages[3].end.kind, SelectorKind::first_after_previous);
  EXPECT_EQ(rule.stages[4].end.kind, SelectorKind::last_before_effect);
  EXPECT_EQ(rule.stages[5].end.kind, SelectorKind::effect);
  // Written back as read.
  EXPECT_EQ(to_string(rule.stages[2].end), "same key vehicle:receive");
  EXPECT_EQ(to_string(rule.stages[4].end), "last vehicle:apply before effect");
}

TEST(StageRule, ErrorsNameTheFileTheLineAndTheField) {
  EXPECT_EQ(rule_error_of("a = first operator:send after cause\nnetwork same key vehicle:receive\nz = effect\n"),
            "stages.txt:2: stage: expected 'NAME = SELECTOR' (e.g. 'network = same key vehicle:receive')");
  EXPECT_NE(rule_error_of("net work = first operator:send after cause\nz = effect\n")
                .find("stages.txt:1: stage name: 'net work' is not a name"),
            std::string::npos);
  EXPECT_EQ(rule_error_of("a = first operator:send after cause\na = effect\n"),
            "stages.txt:2: stage name: 'a' is given twice");
  EXPECT_NE(rule_error_of("a = first operator:send after the cause\nz = effect\n")
                .find("stages.txt:1: selector: 'first operator:send after the cause' is not one of"),
            std::string::npos);
  EXPECT_NE(rule_error_of("a = first operator after cause\nz = effect\n")
                .find("stages.txt:1: selector: 'operator' is not NODE:NAME"),
            std::string::npos);
  EXPECT_NE(rule_error_of("a = last vehicle: before effect\nz = effect\n").find("'vehicle:' is not NODE:NAME"),
            std::string::npos);
  EXPECT_NE(rule_error_of("a = same key vehicle:receive\nz = effect\n").find("stages.txt:1: selector: 'same key' needs"),
            std::string::npos);
  EXPECT_NE(rule_error_of("a = first operator:send after cause\n").find("stages.txt:1: selector: the last stage must end"),
            std::string::npos);
  EXPECT_NE(rule_error_of("z = effect\n").find("stages.txt:1: stages: one stage ending at the effect"),
            std::string::npos);
  EXPECT_NE(rule_error_of("a = first operator:send after cause\nz = effect\nw = effect\n")
                .find("stages.txt:3: stage: after the stage that ends at the effect"),
            std::string::npos);
  EXPECT_NE(rule_error_of("# nothing\n\n").find("stages.txt:2: stages: no stage"), std::string::npos);
}

TEST(StageRule, AMissingFileIsNoInput) {
  try {
    read_stage_rule("/nonexistent/stages.txt");
    FAIL();
  } catch (const core::Error& e) {
    EXPECT_EQ(e.kind(), core::ErrorKind::no_input);
  }
}

}  // namespace m2mlat::analysis::stage_rule_test
