// The scheduling test's result: JSON, text, and the session it is stored as.
#include "m2mlat/selftest/schedtest.hpp"

#include <gtest/gtest.h>
#include <unistd.h>


#include "../sync/fixtures.hpp"  // fixture(): a file of tests/data/sync

namespace m2mlat::selftest {
namespace {

using sync::testing::fixture;

SchedtestRun recorded_run() {
  SchedtestRun run;
  run.options.cpu = 1;
  run.options.duration = std::chrono::seconds(3);
  run.options.histogram_us = 50;
  run.result = parse_cyclictest_json(fixture("cyclictest_1thread.json"), {"cyclictest.json", 0});
  run.start = core::TimePoint::from_ns(core::Clock::realtime, 1'795'269'221'000'000'000);
  run.end = run.start + std::chrono::milliseconds(3050);
  return run;
}

TEST(Schedtest, JsonHoldsSettingsAndResult) {
  const auto j = schedtest_json(recorded_run());
  EXPECT_EQ(j["kind"], "schedtest");
  EXPECT_EQ(j["tool_version"], "2.40");
  EXPECT_EQ(j["settings"]["cpu"], 1);
  EXPECT_EQ(j["settings"]["priority"], 99);
  EXPECT_EQ(j["settings"]["interval_us"], 1000);
  EXPECT_EQ(j["settings"]["duration_s"], 3);
  EXPECT_EQ(j["start_ns"], 1'795'269'221'000'000'000);
  const auto& t = j["threads"][0];
  EXPECT_EQ(t["min_us"], 14);
  EXPECT_EQ(t["max_us"], 2144);
  EXPECT_EQ(t["overflows"], 53);
  EXPECT_EQ(t["histogram"][0], nlohmann::json({14, 3}));
}

TEST(Schedtest, TextShowsSummaryAndBars) {
  const auto text = schedtest_text(recorded_run());
  EXPECT_NE(text.find("cpu 1: 2996 wake-ups, latency min 14 us, avg 30.93 us, max 2144 us, 53 beyond 50 us"),
            std::string::npos)
      << text;
  EXPECT_NE(text.find("30 us       198 " + std::string(50, '#')), std::string::npos) << text;
  // More than 40 buckets are grouped into wider rows.
  auto wide = recorded_run();
  wide.result.threads[0].histogram.clear();
  for (std::int64_t us = 0; us < 100; ++us) wide.result.threads[0].histogram.emplace_back(us, 1);
  const auto grouped = schedtest_text(wide);
  EXPECT_NE(grouped.find("0-2 us         3"), std::string::npos) << grouped;
  EXPECT_EQ(grouped.find("\n         3 us"), std::string::npos) << grouped;
}

TEST(Schedtest, StoredAsAClosedSessionWithTheResult) {
  const std::string path = ::testing::TempDir() + "/schedtest_" + std::to_string(::getpid()) + ".db";
  {
    auto store = store::Store::open(path);
    const auto run = recorded_run();
    const auto id = store_schedtest(store, "board-a", run);
    const auto s = store.session(id);
    ASSERT_TRUE(s);
    EXPECT_EQ(s->label, "schedtest");
    EXPECT_EQ(s->node, "board-a");
    EXPECT_EQ(s->role, core::Role::observer);
    EXPECT_EQ(s->start, run.start);
    ASSERT_TRUE(s->end);
    EXPECT_EQ(*s->end, run.end);
    EXPECT_EQ(nlohmann::json::parse(s->config_json), schedtest_json(run));
    EXPECT_EQ(store.event_count(id), 0);
  }
  for (const char* suffix : {"", "-wal", "-shm"}) ::unlink((path + suffix).c_str());
}

}  // namespace
}  // namespace m2mlat::selftest
