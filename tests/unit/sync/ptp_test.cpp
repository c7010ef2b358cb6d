// pmc output parsing, recorded from real ptp4l 3.1.1 daemons (software timestamping on a veth pair
// between two network namespaces, free_running so that no clock was adjusted), and the PTP sample.
#include "m2mlat/sync/ptp.hpp"

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include "fixtures.hpp"

namespace m2mlat::sync {
namespace {

using testing::fixture;
using testing::ScriptedRunner;

const core::Location kPmcWhere{"pmc", 0};

TEST(PmcOutput, ParsesResponseBlocks) {
  const auto r = parse_pmc_output(fixture("pmc_three_slave.txt"), kPmcWhere);
  ASSERT_EQ(r.size(), 3u);
  EXPECT_EQ(r[0].port_identity, "22b6a3.fffe.ba92f9-0");
  EXPECT_EQ(r[0].seq, 0);
  EXPECT_EQ(r[0].action, "RESPONSE");
  EXPECT_EQ(r[0].id, "TIME_STATUS_NP");
  EXPECT_EQ(r[0].fields.at("master_offset"), "60");
  EXPECT_EQ(r[0].fields.at("gmPresent"), "true");
  EXPECT_EQ(r[0].fields.at("lastGmPhaseChange"), "0x0000'0000000000000000.0000");
  EXPECT_EQ(r[1].id, "CURRENT_DATA_SET");
  EXPECT_EQ(r[1].seq, 1);
  EXPECT_EQ(r[1].fields.at("meanPathDelay"), "2333.0");
  EXPECT_EQ(r[2].id, "PORT_DATA_SET");
  EXPECT_EQ(r[2].port_identity, "22b6a3.fffe.ba92f9-1");
  EXPECT_EQ(r[2].fields.at("portState"), "UNCALIBRATED");
  EXPECT_EQ(r[2].fields.size(), 10u);
}

TEST(PmcOutput, NoDaemonMeansNoResponses) {
  EXPECT_TRUE(parse_pmc_output(fixture("pmc_no_daemon.txt"), kPmcWhere).empty());
}

TEST(PmcOutput, RefusesLinesThatAreNeitherHeaderNorField) {
  EXPECT_THROW(parse_pmc_output("\t\tmaster_offset 5\n", kPmcWhere), core::Error);  // a field before any header
  EXPECT_THROW(parse_pmc_output("hello world\n", kPmcWhere), core::Error);
  EXPECT_THROW(parse_pmc_output("\tabc seq x RESPONSE MANAGEMENT TIME_STATUS_NP\n", kPmcWhere), core::Error);
}

TEST(PtpStatus, SlaveFollowingAGrandmaster) {
  const auto responses = parse_pmc_output(
      fixture("pmc_time_status_slave.txt") + fixture("pmc_current_data_set_slave.txt"), kPmcWhere);
  const auto s = ptp_status(responses, kPmcWhere);
  EXPECT_TRUE(s.gm_present);
  EXPECT_EQ(s.gm_identity, "36199e.fffe.6da772");
  EXPECT_EQ(s.master_offset_ns, 60);
  EXPECT_EQ(s.ingress_time_ns, 1795269187608016381);
  EXPECT_EQ(s.steps_removed, 1);
  EXPECT_EQ(s.mean_path_delay_ns, 2333);

  const auto time = core::TimePoint::from_ns(core::Clock::realtime, 1795269188'000000000);
  const auto sample = ptp_sample(s, time);
  EXPECT_EQ(sample.source, "ptp");
  EXPECT_EQ(sample.offset_ns, 60);
  EXPECT_EQ(sample.max_error_ns, 60 + 2333);
  EXPECT_EQ(sample.est_error_ns, 60);
  EXPECT_TRUE(sample.synchronised);
  EXPECT_EQ(nlohmann::json::parse(sample.detail_json)["gm_identity"], "36199e.fffe.6da772");
}

TEST(PtpStatus, TheGrandmasterItselfIsNotFollowingAnything) {
  const auto responses = parse_pmc_output(
      fixture("pmc_time_status_master.txt") + fixture("pmc_current_data_set_master.txt"), kPmcWhere);
  const auto s = ptp_status(responses, kPmcWhere);
  EXPECT_FALSE(s.gm_present);
  EXPECT_EQ(s.steps_removed, 0);
  EXPECT_FALSE(ptp_sample(s, {}).synchronised);
}

TEST(PtpStatus, MissingResponsesOrFieldsAreDataErrors) {
  EXPECT_THROW(ptp_status(parse_pmc_output(fixture("pmc_time_status_slave.txt"), kPmcWhere), kPmcWhere),
               core::Error);
  auto with = [](const std::string& from, const std::string& to) {
    std::string s = fixture("pmc_three_slave.txt");
    s.replace(s.find(from), from.size(), to);
    return s;
  };
  EXPECT_THROW(ptp_status(parse_pmc_output(with("true", "maybe"), kPmcWhere), kPmcWhere), core::Error);
  EXPECT_THROW(ptp_status(parse_pmc_output(with("2333.0", "lots"), kPmcWhere), kPmcWhere), core::Error);
  EXPECT_THROW(
      ptp_status(parse_pmc_output(with("stepsRemoved     1", "stepsRemoved     -1"), kPmcWhere), kPmcWhere),
      core::Error);
}

TEST(PtpReader, RunsPmcAndReportsNoAnswerAsIoError) {
  ScriptedRunner runner;
  runner.results = {ScriptedRunner::exited(0, fixture("pmc_three_slave.txt"))};
  PmcOptions o;
  o.uds = "/tmp/x/ptp4l.sock";
  EXPECT_EQ(read_ptp(runner, o).master_offset_ns, 60);
  EXPECT_EQ(runner.calls.at(0), (std::vector<std::string>{"pmc", "-u", "-b", "0", "-s", "/tmp/x/ptp4l.sock",
                                                          "GET TIME_STATUS_NP", "GET CURRENT_DATA_SET"}));
  runner.results = {ScriptedRunner::exited(0, fixture("pmc_no_daemon.txt"))};
  try {
    read_ptp(runner, o);
    ADD_FAILURE();
  } catch (const core::Error& e) {
    EXPECT_EQ(e.kind(), core::ErrorKind::io);
    EXPECT_NE(std::string(e.what()).find("no answer"), std::string::npos);
  }
}

}  // namespace
}  // namespace m2mlat::sync
