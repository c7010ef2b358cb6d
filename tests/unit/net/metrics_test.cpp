// The Prometheus text: one HELP/TYPE per family, the samples of the status, escaped labels, exact
// seconds.
#include "m2mlat/net/metrics.hpp"

#include <gtest/gtest.h>

namespace m2mlat::net {
namespace {

// Labels that need escaping: a quote in the node, a backslash and a newline in a channel.
Status awkward_status() {
  Status s;
  s.node = "veh\"icle";
  s.channels = {{"wheel", 10, 2, 1, std::nullopt}, {"a\\b\nc", 3, 0, 0, std::nullopt}};
  s.lost = 1;
  s.dropped = 4;
  s.last_seq = 13;
  s.started_ns = 1'780'304'400'000'000'001;
  return s;
}

TEST(Metrics, SamplesOfTheStatus) {
  const auto text = render_metrics(awkward_status());
  const std::string node = R"(node="veh\"icle")";
  EXPECT_NE(text.find("# TYPE m2mlat_events_total counter\n"), std::string::npos);
  EXPECT_NE(text.find("m2mlat_up{" + node + "} 1\n"), std::string::npos) << text;
  EXPECT_NE(text.find("m2mlat_events_total{" + node + R"(,channel="wheel"} 10)"), std::string::npos) << text;
  EXPECT_NE(text.find("m2mlat_events_total{" + node + R"(,channel="a\\b\nc"} 3)"), std::string::npos) << text;
  EXPECT_NE(text.find("m2mlat_suppressed_edges_total{" + node + R"(,channel="wheel"} 2)"), std::string::npos);
  EXPECT_NE(text.find("m2mlat_lost_events_total{" + node + "} 1\n"), std::string::npos);
  EXPECT_NE(text.find("m2mlat_dropped_edges_total{" + node + "} 4\n"), std::string::npos);
  EXPECT_NE(text.find("m2mlat_last_seq{" + node + "} 13\n"), std::string::npos);
  EXPECT_NE(text.find("m2mlat_session_open{" + node + "} 0\n"), std::string::npos);
  EXPECT_NE(text.find("m2mlat_start_time_seconds{" + node + "} 1780304400.000000001\n"), std::string::npos);
  EXPECT_EQ(text.find("m2mlat_clock_offset_seconds"), std::string::npos);  // no sample yet
  // Every line is a comment or `name{labels} value`, and each family is announced once.
  std::size_t helps = 0;
  for (std::size_t at = 0; (at = text.find("# HELP ", at)) != std::string::npos; ++at) ++helps;
  EXPECT_EQ(helps, 11u);  // 8 of the status, 3 of the connections
  EXPECT_EQ(text.back(), '\n');
}

TEST(Metrics, ClockFamiliesWithASample) {
  auto s = awkward_status();
  store::ClockSample c;
  c.source = "chrony";
  c.offset_ns = -1500;
  c.max_error_ns = 2'000'000;
  c.synchronised = true;
  s.clock = c;
  const auto text = render_metrics(s);
  EXPECT_NE(text.find(R"(m2mlat_clock_offset_seconds{node="veh\"icle",source="chrony"} -0.000001500)"),
            std::string::npos)
      << text;
  EXPECT_NE(text.find(R"(m2mlat_clock_max_error_seconds{node="veh\"icle",source="chrony"} 0.002000000)"),
            std::string::npos);
  EXPECT_NE(text.find(R"(m2mlat_clock_synchronised{node="veh\"icle",source="chrony"} 1)"), std::string::npos);
}

TEST(Metrics, ConnectionCountsByOutcome) {
  ConnectionCounts c;
  c.open = 3;
  c.accepted = 120;
  c.evicted = 7;
  c.timed_out = 50;
  const auto text = render_metrics(awkward_status(), c);
  EXPECT_NE(text.find(R"(m2mlat_http_connections_open{node="veh\"icle"} 3)"), std::string::npos) << text;
  EXPECT_NE(text.find(R"(m2mlat_http_connections_accepted_total{node="veh\"icle"} 120)"),
            std::string::npos);
  EXPECT_NE(text.find(R"(m2mlat_http_connections_ended_early_total{node="veh\"icle",reason="evicted"} 7)"),
            std::string::npos);
  EXPECT_NE(text.find(R"(m2mlat_http_connections_ended_early_total{node="veh\"icle",reason="timed_out"} 50)"),
            std::string::npos);
  EXPECT_NE(text.find(R"(m2mlat_http_connections_ended_early_total{node="veh\"icle",reason="refused"} 0)"),
            std::string::npos);
  EXPECT_NE(text.find("# TYPE m2mlat_http_connections_ended_early_total counter\n"), std::string::npos);
}

// Prometheus' naming rules: every family's TYPE line names a counter ending in _total, or a gauge
// that does not; names are lower-case snake case under m2mlat_; a time is in _seconds.
TEST(Metrics, NamesFollowPrometheusConventions) {
  auto s = awkward_status();
  store::ClockSample c;
  c.source = "chrony";
  s.clock = c;
  ConnectionCounts counts;
  counts.accepted = 1;
  const auto text = render_metrics(s, counts);
  std::size_t families = 0;
  for (std::size_t at = 0; (at = text.find("# TYPE ", at)) != std::string::npos; ++at) {
    const auto line = text.substr(at + 7, text.find('\n', at) - at - 7);
    const auto name = line.substr(0, line.find(' '));
    const auto type = line.substr(line.find(' ') + 1);
    ++families;
    EXPECT_TRUE(name.starts_with("m2mlat_")) << name;
    EXPECT_EQ(name.find_first_not_of("abcdefghijklmnopqrstuvwxyz0123456789_"), std::string::npos) << name;
    if (type == "counter") {
      EXPECT_TRUE(name.ends_with("_total")) << name;
    } else {
      EXPECT_TRUE(type == "gauge" && !name.ends_with("_total")) << name << " " << type;
    }
    if (name.find("time") != std::string::npos || name.find("offset") != std::string::npos ||
        name.find("error") != std::string::npos) {
      EXPECT_TRUE(name.ends_with("_seconds")) << name;
    }
  }
  EXPECT_EQ(families, 14u);
}

}  // namespace
}  // namespace m2mlat::net
