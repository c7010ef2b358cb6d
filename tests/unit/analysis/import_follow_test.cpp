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
LogStamps follower() {
  LogStamps log;
  for (int i = 0; i < 160; ++i) {
    const std::int64_t mono_ns = 1'000 * kS + i * 1'300 * kMs;
    const std::int64_t slew_from = 1'000 * kS + 20 * 1'300 * kMs + 4 * kS;
    const std::int64_t slewed = mono_ns > slew_from ? std::min((mono_ns - slew_from) / 2000, kSize) : 0;
    log.realtime_ns.push_back(kT0 + mono_ns + slewed);
    log.log_time_us.push_back((mono_ns + 20'000 + (i * 7919 % 180) * 1000) / 1000);
  }
  return log;
}

store::ClockStep operator_step(const LogStamps& log) {
  store::ClockStep step;
  step.size_ns = kSize;
  step.earliest_ns = step.at_ns = log.realtime_ns[20] + kSize;
  step.size_max_ns = 300'000;
  step.size_est_ns = 130'000;
  step.origin = "kernel_log";
  return step;
}

// A session of `node` in scenario "k" with one event per stamp and `steps`, ended at the last stamp.
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

std::string kernel_log_config(const std::string& path) {
  return nlohmann::json{{"source", "import"}, {"format", "kernel-log"}, {"path", path}}.dump();
}

TEST_F(ImportFollowTest, AFollowersLogInMemoryTakesOverTheStoredStepOnce) {
  auto s = store::Store::open(path_);
  const auto log = follower();
  // The operator's log imported twice: two sessions with the same step.
  for (int copy = 0; copy < 2; ++copy)
    stored_session(s, "operator", {log.realtime_ns.front(), log.realtime_ns.back()}, "{}", {operator_step(log)});
  const auto vehicle = stored_session(s, "vehicle", log.realtime_ns, kernel_log_config(file("nowhere.log")));

  const auto follow = follow_in_store(s, {"k"}, {{vehicle, log}});
  ASSERT_EQ(follow.followed.size(), 1u);
  EXPECT_EQ(follow.followed[0].follower.id, vehicle);
  EXPECT_TRUE(follow.followed[0].checked);
  ASSERT_EQ(follow.followed[0].steps.size(), 1u);
  EXPECT_EQ(follow.followed[0].steps[0].origin, "followed");
  EXPECT_EQ(follow.followed[0].steps[0].size_ns, kSize);
  EXPECT_EQ(followed_line(follow.followed[0]),
            "vehicle: 1 clock step of another board taken over (seen in its kernel log) -> scenario 'k'");

  // Other scenarios are not looked at; once stored, the step is not taken over again.
  EXPECT_TRUE(follow_in_store(s, {"other"}, {{vehicle, log}}).followed.empty());
  EXPECT_EQ(take_over_steps(s, {"k"}, {{vehicle, log}}, "import", "run").followed.size(), 1u);
  EXPECT_TRUE(follow_in_store(s, {"k"}, {{vehicle, log}}).followed.empty());
  const auto stored = s.sessions().back();
  EXPECT_EQ(stored.node, "vehicle");
  EXPECT_EQ(stored.label, "run");
  EXPECT_EQ(s.event_count(stored.id), 0);
}

TEST_F(ImportFollowTest, AnEarlierLogIsReadAgainFromItsFileOrItsBoardLeftOut) {
  auto s = store::Store::open(path_);
  const auto vehicle = follower();
  const std::string path = file("vehicle.log");
  {
    std::ofstream out(path);
    for (std::size_t i = 0; i < vehicle.realtime_ns.size(); ++i)
      out << fmt::format("[{:5}.{:06}] GPIO_16_IRQ:{}\n", vehicle.log_time_us[i] / 1'000'000,
                         vehicle.log_time_us[i] % 1'000'000, vehicle.realtime_ns[i]);
  }
  const auto id = stored_session(s, "vehicle", vehicle.realtime_ns, kernel_log_config(path));
  const auto step = operator_step(vehicle);
  stored_session(s, "operator", {vehicle.realtime_ns.front(), vehicle.realtime_ns.back()}, "{}", {step});

  const auto read = follow_in_store(s, {"k"});
  ASSERT_EQ(read.followed.size(), 1u);
  EXPECT_EQ(read.followed[0].follower.id, id);
  EXPECT_TRUE(read.followed[0].checked);
  ASSERT_EQ(read.followed[0].steps.size(), 1u);
  EXPECT_EQ(read.followed[0].steps[0].size_ns, kSize);
  EXPECT_TRUE(read.notes.empty());

  // The file gone: the vehicle's stamps after the step are left out (a step of unknown size), said.
  std::remove(path.c_str());
  const auto gone = follow_in_store(s, {"k"});
  ASSERT_EQ(gone.followed.size(), 1u);
  EXPECT_FALSE(gone.followed[0].checked);
  ASSERT_EQ(gone.followed[0].steps.size(), 1u);
  EXPECT_FALSE(gone.followed[0].steps[0].size_ns);
  EXPECT_EQ(gone.followed[0].steps[0].origin, "follow_unchecked");
  EXPECT_EQ(gone.followed[0].steps[0].earliest_ns, step.earliest_ns);
  ASSERT_EQ(gone.notes.size(), 1u);
  EXPECT_NE(gone.notes[0].find("cannot be read again"), std::string::npos);

  // A file that no longer holds the stored events (another log at that path): the same.
  {
    std::ofstream out(path);
    out << "[ 1000.000020] GPIO_16_IRQ:" << kT0 << "\n";
  }
  EXPECT_FALSE(follow_in_store(s, {"k"}).followed.at(0).checked);
}

}  // namespace
}  // namespace m2mlat::analysis::fixture
