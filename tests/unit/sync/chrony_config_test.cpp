// chrony.conf generation for the three modes and the CPU drop-in (that chronyd 4.3 accepts every
// one of them is checked by tests/integration/chrony_config.sh with the real chronyd).
#include "m2mlat/sync/chrony_config.hpp"

#include <gtest/gtest.h>

#include "m2mlat/core/error.hpp"

namespace m2mlat::sync {
namespace {

bool has_line(const std::string& text, const std::string& line) {
  return text.find("\n" + line + "\n") != std::string::npos;
}

TEST(ChronyConfig, CoReferencedReference) {
  ChronyConfigOptions o;
  o.allow = {"10.0.0.0/24"};
  const auto c = chrony_config(o);
  EXPECT_TRUE(has_line(c, "local stratum 1")) << c;
  EXPECT_TRUE(has_line(c, "allow 10.0.0.0/24")) << c;
  EXPECT_TRUE(has_line(c, "makestep 0.005 3")) << c;
  EXPECT_TRUE(has_line(c, "rtcsync")) << c;
  EXPECT_TRUE(has_line(c, "maxslewrate 500")) << c;
  EXPECT_EQ(c.find("server "), std::string::npos);
}

TEST(ChronyConfig, CoReferencedPeerPollsEveryFourSeconds) {
  ChronyConfigOptions o;
  o.role = SyncRole::peer;
  o.reference = "10.0.0.1";
  auto c = chrony_config(o);
  EXPECT_TRUE(has_line(c, "server 10.0.0.1 minpoll 2 maxpoll 2 iburst prefer")) << c;
  EXPECT_EQ(c.find("allow"), std::string::npos);
  EXPECT_EQ(c.find("local stratum"), std::string::npos);
  o.reference_port = 11123;
  o.minpoll = -2;
  o.maxpoll = 0;
  o.hwtimestamp = "eth0";
  c = chrony_config(o);
  EXPECT_TRUE(has_line(c, "server 10.0.0.1 port 11123 minpoll -2 maxpoll 0 iburst prefer")) << c;
  EXPECT_TRUE(has_line(c, "hwtimestamp eth0")) << c;
}

TEST(ChronyConfig, AutonomousAndGnss) {
  ChronyConfigOptions o;
  o.mode = SyncMode::autonomous;
  EXPECT_TRUE(has_line(chrony_config(o), "pool 2.debian.pool.ntp.org iburst"));
  o.servers = {"ntp1.example.org"};
  auto c = chrony_config(o);
  EXPECT_TRUE(has_line(c, "server ntp1.example.org iburst"));
  EXPECT_EQ(c.find("pool "), std::string::npos);  // given servers replace the default pool

  o.mode = SyncMode::gnss_pps;
  c = chrony_config(o);
  EXPECT_TRUE(has_line(c, "refclock SHM 0 refid NMEA offset 0.0 delay 0.2 noselect")) << c;
  EXPECT_TRUE(has_line(c, "refclock PPS /dev/pps0 lock NMEA refid PPS prefer")) << c;
  EXPECT_NE(c.find("dtoverlay=pps-gpio"), std::string::npos);
  o.nmea = "/run/chrony.ttyAMA0.sock";
  EXPECT_TRUE(has_line(chrony_config(o),
                       "refclock SOCK /run/chrony.ttyAMA0.sock refid NMEA offset 0.0 delay 0.2 noselect"));
}

TEST(ChronyConfig, RefusesMissingOrUnsafeValues) {
  auto usage = [](const ChronyConfigOptions& o) {
    try {
      chrony_config(o);
    } catch (const core::Error& e) {
      return e.kind() == core::ErrorKind::usage;
    }
    return false;
  };
  ChronyConfigOptions o;
  EXPECT_TRUE(usage(o));  // reference without --allow
  o.allow = {"10.0.0.0/24\nserver evil"};
  EXPECT_TRUE(usage(o));  // no second directive through a value
  o.allow = {"10.0.0.0/24"};
  o.local_stratum = 16;
  EXPECT_TRUE(usage(o));
  ChronyConfigOptions p;
  p.role = SyncRole::peer;
  EXPECT_TRUE(usage(p));  // peer without --reference
  p.reference = "10.0.0.1";
  p.minpoll = 3;
  p.maxpoll = 2;
  EXPECT_TRUE(usage(p));
  EXPECT_THROW(parse_sync_mode("sideways"), core::Error);
  EXPECT_THROW(parse_sync_role("boss"), core::Error);
  EXPECT_EQ(parse_sync_mode("gnss-pps"), SyncMode::gnss_pps);
  EXPECT_EQ(to_string(parse_sync_mode("co-referenced")), "co-referenced");
}

TEST(ChronyConfig, CpuDropin) {
  const auto d = chrony_cpu_dropin(3);
  EXPECT_NE(d.find("[Service]\nCPUAffinity=3\n"), std::string::npos) << d;
  EXPECT_THROW(chrony_cpu_dropin(-1), core::Error);
}

}  // namespace
}  // namespace m2mlat::sync
