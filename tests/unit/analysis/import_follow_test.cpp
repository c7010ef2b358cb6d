// The follow of the other board's step across imports: against the steps a store holds, and an
// earlier board's kernel log read again from its file.
#include "m2mlat/analysis/import_follow.hpp"

#include <fmt/format.h>
#include <gtest/gtest.h>

#include <cstdio>
#include <fstream>
#include <nlohmann/json.hpp>

#include "store_fixture.hpp"

namespace m2mlat::analysis::fixture {
namespace {

using ImportFollowTest = StoreTest;

constexpr std::int64_t kSize = 40 * kMs;  // the operator's step

// A co-referenced vehicle's kernel log: 160 edges 1.3 s apart, printk 20-200 us after each; from 4 s
// after line 20 its clock slews at 500 ppm onto the operator's timescale, stepped by kSize there.
ImportedLog follower() {
  ImportedLog log;
  log.node = "vehicle";
  log.scenario = "k";
  for (int i = 0; i < 160; ++i) {
    const std::int64_t mono_ns = 1'000 * kS + i * 1'300 * kMs;
    const std::int64_t slew_from = 1'000 * kS + 20 * 1'300 * kMs + 4 * kS;
    const std::int64_t slewed = mono_ns > slew_from ? std::min((mono_ns - slew_from) / 2000, kSize) : 0;
    log.realtime_ns.push_back(kT0 + mono_ns + slewed);
    log.log_time_us.push_back((mono_ns + 20'000 + (i * 7919 % 180) * 1000) / 1000);
  }
  return log;
}

store::ClockStep operator_step(const ImportedLog& log) {
  store::ClockStep step;
  step.size_ns = kSize;
  step.earliest_ns = step.at_ns = log.realtime_ns[20] + kSize;
  step.size_max_ns = 300'000;
  step.size_est_ns = 130'000;
  step.origin = "kernel_log";
  return step;
}

// A session of `node` with one event per stamp and `steps`, ended at the last stamp.
std::int64_t stored_session(store::Store& s, const std::string& node, const std::vector<std::int64_t>& stamps,
                            const std::string& config = "{}", const std::vector<store::ClockStep>& steps = {}) {
  store::Session info;
  info.scenario = "k";
  info.node = node;
  info.role = node == "operator" ? core::Role::cause : core::Role::effect;
  info.config_json = config;
  info.start = rt(stamps.front());
  const auto id = s.begin_session(info);
  std::vector<core::Event> events;
  for (const auto t : stamps) events.push_back(edge(node, "gpio16", t));
  s.append_events(id, events);
  for (const auto& step : steps) {
    auto sample = store::step_clock_sample(step);
    sample.session_id = id;
    s.append_clock_samples(std::vector{sample});
  }
  s.end_session(id, rt(stamps.back()));
  return id;
}

TEST_F(ImportFollowTest, TheFollowerImportedSecondTakesOverTheStoredStepOnce) {
  auto s = store::Store::open(path_);
  const auto log = follower();
  const auto step = operator_step(log);
  // The operator's log imported twice: two sessions with the same step.
  for (int copy = 0; copy < 2; ++copy)
    stored_session(s, "operator", {log.realtime_ns.front(), log.realtime_ns.back()}, "{}", {step});
  const auto follow = follow_across_import(std::vector{log}, s);
  ASSERT_EQ(follow.of_log.size(), 1u);
  ASSERT_EQ(follow.of_log[0].size(), 1u);
  EXPECT_EQ(follow.of_log[0][0].origin, "followed");
  EXPECT_EQ(follow.of_log[0][0].size_ns, kSize);
  EXPECT_TRUE(follow.earlier.empty());

  // In another scenario: nothing to follow.
  auto other = log;
  other.scenario = "other";
  EXPECT_TRUE(follow_across_import(std::vector{other}, s).of_log[0].empty());
}

TEST_F(ImportFollowTest, TheFollowerImportedFirstIsReadAgainFromItsFileOrLeftOut) {
  auto s = store::Store::open(path_);
  const auto vehicle = follower();
  const std::string file = this->file("vehicle.log");
  {
    std::ofstream out(file);
    for (std::size_t i = 0; i < vehicle.realtime_ns.size(); ++i)
      out << fmt::format("[{:5}.{:06}] GPIO_16_IRQ:{}\n", vehicle.log_time_us[i] / 1'000'000,
                         vehicle.log_time_us[i] % 1'000'000, vehicle.realtime_ns[i]);
  }
  const auto id = stored_session(s, "vehicle", vehicle.realtime_ns,
                                 nlohmann::json{{"source", "import"}, {"format", "kernel-log"}, {"path", file}}.dump());
  ImportedLog op;
  op.node = "operator";
  op.scenario = "k";
  op.steps = {operator_step(vehicle)};

  const auto read = follow_across_import(std::vector{op}, s);
  EXPECT_TRUE(read.of_log[0].empty());
  ASSERT_EQ(read.earlier.size(), 1u);
  EXPECT_EQ(read.earlier[0].earlier.id, id);
  EXPECT_TRUE(read.earlier[0].checked);
  ASSERT_EQ(read.earlier[0].steps.size(), 1u);
  EXPECT_EQ(read.earlier[0].steps[0].size_ns, kSize);
  EXPECT_TRUE(read.notes.empty());

  // The file gone: the vehicle's stamps after the step are left out (a step of unknown size), said.
  std::remove(file.c_str());
  const auto gone = follow_across_import(std::vector{op}, s);
  ASSERT_EQ(gone.earlier.size(), 1u);
  EXPECT_FALSE(gone.earlier[0].checked);
  ASSERT_EQ(gone.earlier[0].steps.size(), 1u);
  EXPECT_FALSE(gone.earlier[0].steps[0].size_ns);
  EXPECT_EQ(gone.earlier[0].steps[0].origin, "follow_unchecked");
  EXPECT_EQ(gone.earlier[0].steps[0].earliest_ns, op.steps[0].earliest_ns);
  ASSERT_EQ(gone.notes.size(), 1u);
  EXPECT_NE(gone.notes[0].find("cannot be read again"), std::string::npos);

  // A file that no longer holds the stored events (another log at that path): the same.
  {
    std::ofstream out(file);
    out << "[ 1000.000020] GPIO_16_IRQ:" << kT0 << "\n";
  }
  EXPECT_FALSE(follow_across_import(std::vector{op}, s).earlier.at(0).checked);
}

}  // namespace
}  // namespace m2mlat::analysis::fixture
