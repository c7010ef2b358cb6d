// cyclictest output parsing (JSON and histogram text recorded from a real 3 s run of rt-tests 2.40
// here: --affinity=1 --histogram=50) and the runner with a scripted cyclictest.
#include "m2mlat/selftest/cyclictest.hpp"

#include <gtest/gtest.h>

#include <fstream>
#include <numeric>

#include "../sync/fixtures.hpp"  // fixture(): a file of tests/data/sync

namespace m2mlat::selftest {
namespace {

using sync::testing::fixture;

const core::Location kWhere{"cyclictest", 0};

TEST(CyclictestJson, ParsesARealRun) {
  const auto r = parse_cyclictest_json(fixture("cyclictest_1thread.json"), kWhere);
  EXPECT_EQ(r.version, "2.40");
  EXPECT_EQ(r.return_code, 0);
  EXPECT_NE(r.cmdline.find("--histogram=50"), std::string::npos);
  EXPECT_FALSE(r.realtime_kernel);
  ASSERT_EQ(r.threads.size(), 1u);
  const auto& t = r.threads[0];
  EXPECT_EQ(t.cpu, 1);
  EXPECT_EQ(t.cycles, 2996u);
  EXPECT_EQ(t.min_us, 14);
  EXPECT_EQ(t.max_us, 2144);
  EXPECT_DOUBLE_EQ(t.avg_us, 30.93);
  ASSERT_EQ(t.histogram.size(), 36u);  // buckets 14..49 us
  EXPECT_EQ(t.histogram.front(), (std::pair<std::int64_t, std::uint64_t>{14, 3}));
  EXPECT_EQ(t.histogram.back(), (std::pair<std::int64_t, std::uint64_t>{49, 4}));
  EXPECT_EQ(t.overflows, 53u);  // 2996 cycles - 2943 in the histogram
}

TEST(CyclictestHistogram, ParsesTheTextOfTheSameRun) {
  const auto h = parse_cyclictest_histogram(fixture("cyclictest_1thread_histogram.txt"), kWhere);
  ASSERT_EQ(h.counts.size(), 1u);
  EXPECT_EQ(h.counts[0].size(), 50u);
  EXPECT_EQ(h.counts[0][14], 3u);
  EXPECT_EQ(h.counts[0][30], 198u);
  EXPECT_EQ(std::accumulate(h.counts[0].begin(), h.counts[0].end(), std::uint64_t{0}), 2943u);
  EXPECT_EQ(h.total, std::vector<std::uint64_t>{2943});
  EXPECT_EQ(h.overflows, std::vector<std::uint64_t>{53});
  EXPECT_EQ(h.min_us, std::vector<std::int64_t>{14});
  EXPECT_EQ(h.avg_us, std::vector<std::int64_t>{30});
  EXPECT_EQ(h.max_us, std::vector<std::int64_t>{2144});
}

TEST(CyclictestHistogram, TwoThreadsAndMalformedText) {
  const std::string two =
      "# Histogram\n000000 000001 000000\n000001 000002 000003\n# Total: 000000003 000000003\n"
      "# Min Latencies: 00000 00001\n# Avg Latencies: 00001 00001\n# Max Latencies: 00001 00001\n"
      "# Histogram Overflows: 00000 00000\n";
  const auto h = parse_cyclictest_histogram(two, kWhere);
  ASSERT_EQ(h.counts.size(), 2u);
  EXPECT_EQ(h.counts[1], (std::vector<std::uint64_t>{0, 3}));
  auto refused = [](const std::string& text) {
    try {
      parse_cyclictest_histogram(text, kWhere);
    } catch (const core::Error& e) {
      return e.kind() == core::ErrorKind::data;
    }
    return false;
  };
  EXPECT_TRUE(refused(""));
  EXPECT_TRUE(refused("000000 000001\n"));  // no summary
  std::string wrong_total = two;
  wrong_total.replace(wrong_total.find("000000003 000000003"), 19, "000000004 000000003");
  EXPECT_TRUE(refused(wrong_total));
  std::string gap = two;
  gap.replace(gap.find("000001 000002"), 6, "000005");
  EXPECT_TRUE(refused(gap));
  std::string ragged = two;
  ragged.replace(ragged.find("000001 000002 000003"), 20, "000001 000002");
  EXPECT_TRUE(refused(ragged));
  EXPECT_TRUE(refused("# Total: 1 1\n000000 000001\n"));  // a summary before the buckets sets the count
  EXPECT_TRUE(refused("# Total: 1\n000000 000001\n# Min Latencies: 0\n"));  // summary lines missing
}

TEST(CyclictestJson, RefusesMalformedDocuments) {
  auto refused = [](const std::string& text, const std::string& needle) {
    try {
      parse_cyclictest_json(text, kWhere);
    } catch (const core::Error& e) {
      EXPECT_NE(std::string(e.what()).find(needle), std::string::npos) << e.what();
      return e.kind() == core::ErrorKind::data;
    }
    return false;
  };
  const std::string good = fixture("cyclictest_1thread.json");
  auto with = [&](const std::string& from, const std::string& to) {
    std::string s = good;
    s.replace(s.find(from), from.size(), to);
    return s;
  };
  EXPECT_TRUE(refused("{", "not JSON"));
  EXPECT_TRUE(refused("[]", "not a JSON object"));
  EXPECT_TRUE(refused(with("\"file_version\": 1", "\"file_version\": 2"), "file_version"));
  EXPECT_TRUE(refused(with("\"cycles\": 2996", "\"cycles\": 100"), "more than the 100 cycles"));
  EXPECT_TRUE(refused(with("\"min\": 14", "\"min\": \"14\""), "thread.0.min"));
  EXPECT_TRUE(refused(with("\"num_threads\": 1", "\"num_threads\": 2"), "thread.1"));
  EXPECT_TRUE(refused(with("\"14\": 3", "\"x\": 3"), "bucket 'x'"));
}

// Answers like cyclictest: writes the JSON to the --json= path of its command line and prints the
// histogram text.
class FakeCyclictest final : public process::CommandRunner {
 public:
  std::string json, histogram;
  int exit_code = 0;
  std::vector<std::string> argv;
  process::CommandResult run(const std::vector<std::string>& args, core::Duration) override {
    argv = args;
    for (const auto& a : args)
      if (a.rfind("--json=", 0) == 0) std::ofstream(a.substr(7)) << json;
    process::CommandResult r;
    r.started = true;
    r.exit_code = exit_code;
    r.out = histogram;
    if (exit_code != 0) r.err = "Unable to change scheduling policy!\n";
    return r;
  }
};

TEST(RunCyclictest, RunsWithTheReferenceRigsSettingsAndChecksAgreement) {
  FakeCyclictest fake;
  fake.json = fixture("cyclictest_1thread.json");
  fake.histogram = fixture("cyclictest_1thread_histogram.txt");
  CyclictestOptions o;
  o.cpu = 1;
  o.duration = std::chrono::seconds(3);
  o.histogram_us = 50;
  const auto r = run_cyclictest(fake, o);
  EXPECT_EQ(r.threads.at(0).overflows, 53u);
  ASSERT_EQ(fake.argv.size(), 10u);
  EXPECT_EQ(fake.argv[0], "cyclictest");
  EXPECT_EQ(fake.argv[1], "--mlockall");
  EXPECT_EQ(fake.argv[2], "--priority=99");
  EXPECT_EQ(fake.argv[3], "--affinity=1");
  EXPECT_EQ(fake.argv[4], "--threads=1");
  EXPECT_EQ(fake.argv[5], "--interval=1000");
  EXPECT_EQ(fake.argv[6], "--duration=3s");
  EXPECT_EQ(fake.argv[7], "--histogram=50");
  EXPECT_EQ(fake.argv[8].rfind("--json=/tmp/m2mlat-cyclictest-", 0), 0u);
  EXPECT_EQ(fake.argv[9], "-q");
  std::ifstream gone(fake.argv[8].substr(7));
  EXPECT_FALSE(gone.good());  // the temporary file is removed

  // Text and JSON of different runs disagree: refused.
  fake.histogram.replace(fake.histogram.find("Histogram Overflows: 00053"), 26, "Histogram Overflows: 00054");
  EXPECT_THROW(run_cyclictest(fake, o), core::Error);
}

TEST(RunCyclictest, FailureCarriesCyclictestsMessage) {
  FakeCyclictest fake;
  fake.exit_code = 255;
  try {
    run_cyclictest(fake, {});
    ADD_FAILURE();
  } catch (const core::Error& e) {
    EXPECT_EQ(e.kind(), core::ErrorKind::io);
    EXPECT_NE(std::string(e.what()).find("Unable to change scheduling policy"), std::string::npos)
        << e.what();
  }
  CyclictestOptions bad;
  bad.priority = 100;
  EXPECT_THROW(run_cyclictest(fake, bad), core::Error);
  bad = {};
  bad.duration = std::chrono::milliseconds(500);
  EXPECT_THROW(run_cyclictest(fake, bad), core::Error);
}

}  // namespace
}  // namespace m2mlat::selftest
