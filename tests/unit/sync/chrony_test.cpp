// chronyc CSV parsing (recorded from real chronyd 4.3 daemons), the chrony clock sample, and the
// chronyc runner's command line and failures.
#include "m2mlat/sync/chrony.hpp"

#include <gtest/gtest.h>

#include <limits>

#include <nlohmann/json.hpp>

#include "fixtures.hpp"

namespace m2mlat::sync {
namespace {

using testing::fixture;
using testing::ScriptedRunner;

const core::Location kWhere{"chronyc", 0};

TEST(ChronyTracking, ParsesASynchronisedClient) {
  // 7F000001,127.0.0.1,2,1795269144.625571300,-0.000001284,0.000000013,0.000000012,-0.004,0.000,0.020,
  // 0.000006085,0.000000429,0.3,Normal  (text form: "0.000001284 seconds fast of NTP time", "0.004 ppm slow")
  const auto t = parse_chrony_tracking_line(fixture("chronyc_tracking_synchronised.csv"), kWhere);
  EXPECT_EQ(t.ref_id, 0x7F000001u);
  EXPECT_EQ(t.ref_name, "127.0.0.1");
  EXPECT_EQ(t.stratum, 2);
  EXPECT_EQ(t.ref_time_ns, 1795269144625571300);
  EXPECT_EQ(t.system_offset_ns, 1284);  // fast = ahead = positive
  EXPECT_EQ(t.last_offset_ns, 13);
  EXPECT_EQ(t.rms_offset_ns, 12);
  EXPECT_DOUBLE_EQ(t.freq_ppm, -0.004);  // slow = negative
  EXPECT_DOUBLE_EQ(t.residual_freq_ppm, 0.0);
  EXPECT_DOUBLE_EQ(t.skew_ppm, 0.020);
  EXPECT_EQ(t.root_delay_ns, 6085);
  EXPECT_EQ(t.root_dispersion_ns, 429);
  EXPECT_EQ(t.update_interval_ns, 300'000'000);
  EXPECT_EQ(t.leap_status, "Normal");
  EXPECT_TRUE(t.synchronised());
  // The text form of the same daemon says "fast": the sign convention matches chronyc's own words.
  EXPECT_NE(fixture("chronyc_tracking_synchronised.txt").find("seconds fast of NTP time"), std::string::npos);
}

TEST(ChronyTracking, ParsesTheLocalReferenceAndAnUnsynchronisedClient) {
  const auto local = parse_chrony_tracking_line(fixture("chronyc_tracking_local_reference.csv"), kWhere);
  EXPECT_EQ(local.ref_id, 0x7F7F0101u);  // "LOCL": local stratum
  EXPECT_EQ(local.ref_name, "");
  EXPECT_EQ(local.stratum, 1);
  EXPECT_TRUE(local.synchronised());

  const auto none = parse_chrony_tracking_line(fixture("chronyc_tracking_unsynchronised.csv"), kWhere);
  EXPECT_EQ(none.ref_id, 0u);
  EXPECT_EQ(none.stratum, 0);
  EXPECT_EQ(none.ref_time_ns, 0);
  EXPECT_EQ(none.root_delay_ns, 1'000'000'000);
  EXPECT_EQ(none.leap_status, "Not synchronised");
  EXPECT_FALSE(none.synchronised());
}

TEST(ChronySources, ParsesSelectedAndUnusableSources) {
  const auto s = parse_chrony_source_line(fixture("chronyc_sources_synchronised.csv"), kWhere);
  EXPECT_EQ(s.mode, '^');
  EXPECT_EQ(s.state, '*');
  EXPECT_EQ(s.name, "127.0.0.1");
  EXPECT_EQ(s.stratum, 1);
  EXPECT_EQ(s.poll, -2);
  EXPECT_EQ(s.reach, 0377);
  ASSERT_TRUE(s.last_rx_s.has_value());
  EXPECT_EQ(*s.last_rx_s, 0);
  EXPECT_EQ(s.adjusted_offset_ns, 116);
  EXPECT_EQ(s.measured_offset_ns, 129);
  EXPECT_EQ(s.error_ns, 3196);

  const auto u = parse_chrony_source_line(fixture("chronyc_sources_unsynchronised.csv"), kWhere);
  EXPECT_EQ(u.state, '?');
  EXPECT_EQ(u.reach, 0);
  EXPECT_FALSE(u.last_rx_s.has_value());  // 4294967295: never
}

TEST(ChronycOutput, TrackingAndSourcesTogether) {
  const std::string text =
      fixture("chronyc_tracking_synchronised.csv") + fixture("chronyc_sources_synchronised.csv");
  const auto r = parse_chronyc_output(text, kWhere);
  EXPECT_EQ(r.tracking.stratum, 2);
  ASSERT_EQ(r.sources.size(), 1u);
  EXPECT_EQ(r.sources[0].name, "127.0.0.1");
  // No sources at all (the reference) is fine.
  EXPECT_TRUE(parse_chronyc_output(fixture("chronyc_tracking_local_reference.csv"), kWhere).sources.empty());
}

void expect_data_error(const std::string& text, const std::string& needle) {
  try {
    parse_chronyc_output(text, kWhere);
    ADD_FAILURE() << "accepted: " << text;
  } catch (const core::Error& e) {
    EXPECT_EQ(e.kind(), core::ErrorKind::data);
    EXPECT_NE(std::string(e.what()).find(needle), std::string::npos) << e.what();
  }
}

TEST(ChronycOutput, RefusesMalformedOutputNamingLineAndField) {
  const std::string good = fixture("chronyc_tracking_synchronised.csv");
  auto replace = [&](const std::string& from, const std::string& to) {
    std::string s = good;
    s.replace(s.find(from), from.size(), to);
    return s;
  };
  expect_data_error("", "no tracking line");
  expect_data_error(good + good, "chronyc:2: a second tracking line");
  expect_data_error(replace(",2,", ",two,"), "field 'stratum'");
  expect_data_error(replace(",2,", ",17,"), "field 'stratum'");
  expect_data_error(replace("7F000001", "7F0000G1"), "field 'reference id'");
  expect_data_error(replace("7F000001", "7F00001"), "field 'reference id'");
  expect_data_error(replace("Normal", "Fine"), "field 'leap status'");
  expect_data_error(replace("-0.000001284", "-0.0000012845"), "field 'system time'");  // 10 decimals
  expect_data_error(replace("0.020,", "0.02x,"), "field 'skew'");
  expect_data_error(replace(",Normal", ""), "fields");
  expect_data_error(good + "^,*,127.0.0.1,1,-2,378,0,0.0,0.0,0.0\n",
                    "chronyc:2: field 'reach'");  // not octal
  expect_data_error(good + "^,!,127.0.0.1,1,-2,377,0,0.0,0.0,0.0\n", "field 'state'");
  expect_data_error(good + "^,*,127.0.0.1,1,-2,377,0,0.0,0.0,-0.1\n", "field 'error'");
}

TEST(ChronySample, ErrorBoundsFromTracking) {
  const auto r = parse_chronyc_output(
      fixture("chronyc_tracking_synchronised.csv") + fixture("chronyc_sources_synchronised.csv"), kWhere);
  const auto time = core::TimePoint::from_ns(core::Clock::realtime, 1795269145'000000000);
  const auto s = chrony_sample(r, time);
  EXPECT_EQ(s.source, "chrony");
  EXPECT_EQ(s.time, time);
  EXPECT_EQ(s.offset_ns, 1284);
  EXPECT_EQ(s.max_error_ns, 1284 + 429 + 6085 / 2);
  EXPECT_EQ(s.est_error_ns, 1284);  // max(RMS 12, |offset| 1284)
  EXPECT_TRUE(s.synchronised);
  const auto d = nlohmann::json::parse(s.detail_json);
  EXPECT_EQ(d["ref_id"], "7F000001");
  EXPECT_EQ(d["stratum"], 2);
  EXPECT_EQ(d["root_delay_ns"], 6085);
  ASSERT_EQ(d["sources"].size(), 1u);
  EXPECT_EQ(d["sources"][0]["state"], "*");
  EXPECT_EQ(d["sources"][0]["error_ns"], 3196);

  auto unsynced = parse_chronyc_output(fixture("chronyc_tracking_unsynchronised.csv"), kWhere);
  const auto u = chrony_sample(unsynced, time);
  EXPECT_FALSE(u.synchronised);
  EXPECT_EQ(u.max_error_ns, 1'000'000'000 + 500'000'000);
}

TEST(ChronySample, AnAbsurdReportGivesTheLargestBoundNotAnOverflow) {
  // Offsets and dispersions of billions of seconds parse (they fit in int64 ns); their sum does not.
  ChronyReport r;
  r.tracking.system_offset_ns = -8'000'001'284'000'000'000;
  r.tracking.root_dispersion_ns = 3'500'003'042'500'000'000;
  r.tracking.root_delay_ns = 7'000'006'085'000'000'000;
  const auto s = chrony_sample(r, core::TimePoint::from_ns(core::Clock::realtime, 0));
  EXPECT_EQ(s.max_error_ns, std::numeric_limits<std::int64_t>::max());
  r.tracking.system_offset_ns = std::numeric_limits<std::int64_t>::min();
  EXPECT_EQ(chrony_sample(r, {}).max_error_ns, std::numeric_limits<std::int64_t>::max());
}

TEST(ChronyReader, RunsChronycWithTheSocketAndParses) {
  ScriptedRunner runner;
  runner.results = {ScriptedRunner::exited(
      0, fixture("chronyc_tracking_synchronised.csv") + fixture("chronyc_sources_synchronised.csv"))};
  ChronycOptions o;
  o.host = "/tmp/x/chronyd.sock";
  const auto r = read_chrony(runner, o);
  EXPECT_EQ(r.tracking.stratum, 2);
  ASSERT_EQ(runner.calls.size(), 1u);
  EXPECT_EQ(runner.calls[0], (std::vector<std::string>{"chronyc", "-c", "-n", "-m", "-h",
                                                       "/tmp/x/chronyd.sock", "tracking", "sources"}));
  o.host = "192.0.2.1";
  o.port = 10323;
  EXPECT_EQ(chronyc_argv(o), (std::vector<std::string>{"chronyc", "-c", "-n", "-m", "-h", "192.0.2.1", "-p",
                                                       "10323", "tracking", "sources"}));
}

TEST(ChronyReader, FailuresAreIoErrorsWithChronycsMessage) {
  ScriptedRunner runner;
  runner.results = {ScriptedRunner::exited(1, "506 Cannot talk to daemon\n")};
  try {
    read_chrony(runner, {});
    ADD_FAILURE();
  } catch (const core::Error& e) {
    EXPECT_EQ(e.kind(), core::ErrorKind::io);
    EXPECT_NE(std::string(e.what()).find("exit status 1: 506 Cannot talk to daemon"), std::string::npos)
        << e.what();
  }
  process::CommandResult not_started;
  not_started.err = "chronyc: No such file or directory";
  runner.results = {not_started};
  EXPECT_THROW(read_chrony(runner, {}), core::Error);
  runner.results = {ScriptedRunner::exited(0, "garbage\n")};
  try {
    read_chrony(runner, {});
    ADD_FAILURE();
  } catch (const core::Error& e) {
    EXPECT_EQ(e.kind(), core::ErrorKind::data);
  }
}

}  // namespace
}  // namespace m2mlat::sync
