// The recorder's TOML configuration: the documented example, and errors naming file, line and key.
#include "m2mlat/capture/record_config.hpp"

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>

#include "m2mlat/core/error.hpp"

namespace m2mlat::capture {
namespace {

std::string error_of(const std::string& text) {
  try {
    parse_record_config(text, "vehicle.toml");
  } catch (const core::Error& e) {
    EXPECT_EQ(e.kind(), core::ErrorKind::data);
    return e.what();
  }
  return "no error";
}

TEST(RecordConfig, ReadsTheShippedExample) {
  const auto c = load_record_config(std::string(M2MLAT_TEST_DATA) + "/../../docs/record-example.toml");
  EXPECT_EQ(c.node, "vehicle");
  EXPECT_EQ(c.role, core::Role::effect);
  ASSERT_EQ(c.channels.size(), 1u);
  const auto& wheel = c.channels[0];
  EXPECT_EQ(wheel.name, "wheel");
  EXPECT_EQ(wheel.chip, "pinctrl-rp1");
  EXPECT_EQ(wheel.line, "GPIO16");
  EXPECT_EQ(wheel.edges, Edges::falling);
  EXPECT_EQ(wheel.bias, Bias::pull_up);
  EXPECT_EQ(wheel.refractory, std::chrono::milliseconds(10));
  EXPECT_EQ(wheel.debounce.count(), 0);
  EXPECT_EQ(c.channel_keys[0].count("edges"), 1u);
  EXPECT_EQ(c.channel_keys[0].count("clock"), 0u);
}

TEST(RecordConfig, ReadsEverySection) {
  const auto c = parse_record_config(
      "node = \"operator\"\nrole = \"cause\"\nsource = \"kmsg\"\nkmsg = \"/var/log/kern.log\"\n"
      "[[channel]]\nname = \"a\"\nline = 16\nclock = \"monotonic\"\nactive_low = true\ndebounce = \"1ms\"\n"
      "[[channel]]\nname = \"b\"\nline = \"GPIO17\"\nedges = \"both\"\n"
      "[rt]\npriority = 80\ncpu = 3\nmlock = true\nirq_cpu = 2\n"
      "[store]\nbatch = 64\ncommit_interval = \"50ms\"\ndurability = \"full\"\n"
      "[clock]\nmonitor = true\nkernel_interval = \"2s\"\nchrony_interval = \"4s\"\nptp_interval = 0\n",
      "x.toml");
  EXPECT_EQ(c.role, core::Role::cause);
  EXPECT_EQ(c.source, "kmsg");
  EXPECT_EQ(c.kmsg, "/var/log/kern.log");
  ASSERT_EQ(c.channels.size(), 2u);
  EXPECT_EQ(c.channels[0].line, "16");
  EXPECT_EQ(c.channels[0].clock, EventClock::monotonic);
  EXPECT_TRUE(c.channels[0].active_low);
  EXPECT_EQ(c.channels[0].debounce, std::chrono::milliseconds(1));
  EXPECT_EQ(c.channels[1].edges, Edges::both);
  EXPECT_EQ(c.rt_priority, 80);
  EXPECT_EQ(c.cpu, 3);
  EXPECT_EQ(c.irq_cpu, 2);
  EXPECT_EQ(c.mlock, true);
  EXPECT_EQ(c.batch, 64);
  EXPECT_EQ(c.commit_interval, std::chrono::milliseconds(50));
  EXPECT_EQ(c.durability, "full");
  EXPECT_EQ(c.clock_monitor, true);
  EXPECT_EQ(c.kernel_interval, std::chrono::seconds(2));
  EXPECT_EQ(c.chrony_interval, std::chrono::seconds(4));
  EXPECT_EQ(c.ptp_interval, core::Duration{0});
}

TEST(RecordConfig, ErrorsNameTheFileLineAndKey) {
  EXPECT_EQ(error_of("node = \"v\"\n[[channel]]\nname = \"wheel\"\nline = \"GPIO16\"\nedges = \"fallin\"\n"),
            "vehicle.toml:5:9: channel[1].edges: edges 'fallin': use falling, rising or both");
  EXPECT_EQ(
      error_of("node = \"v\"\nrefractory = \"10ms\"\n"),
      "vehicle.toml:2:1: refractory: unknown key (node, role, scenario, label, source, kmsg, [[channel]], "
      "[rt], [store], [clock])");
  const auto bad_duration = error_of("[[channel]]\nname = \"w\"\nline = 3\nrefractory = \"10\"\n");
  EXPECT_NE(bad_duration.find("vehicle.toml:4:14: channel[1].refractory:"), std::string::npos)
      << bad_duration;
  const auto bad_toml = error_of("node = \"v\nrole = 1\n");
  EXPECT_NE(bad_toml.find("vehicle.toml:1:"), std::string::npos) << bad_toml;
  const auto no_line = error_of("[[channel]]\nname = \"w\"\n");
  EXPECT_NE(no_line.find("vehicle.toml:1:1: channel[1].line"), std::string::npos) << no_line;
  const auto range = error_of("[rt]\npriority = 100\n");
  EXPECT_NE(range.find("vehicle.toml:2:12: rt.priority: must be in 1..99"), std::string::npos) << range;
  const auto twice = error_of("[[channel]]\nname = \"w\"\nline = 1\n[[channel]]\nname = \"w\"\nline = 2\n");
  EXPECT_NE(twice.find("defined twice"), std::string::npos) << twice;
}

TEST(RecordConfig, AFileCutMidWriteIsRefused) {
  // "batch = 51" is valid TOML: only the missing newline shows that "batch = 512" was cut.
  const auto path =
      (std::filesystem::temp_directory_path() / ("m2mlat-cut-" + std::to_string(::getpid()) + ".toml"))
          .string();
  std::ofstream(path) << "node = \"vehicle\"\n[store]\nbatch = 51";
  try {
    load_record_config(path);
    ADD_FAILURE() << "a cut configuration was read";
  } catch (const core::Error& e) {
    EXPECT_EQ(e.kind(), core::ErrorKind::data);
    EXPECT_NE(std::string(e.what()).find(path + ":3: the last line does not end with a newline"),
              std::string::npos)
        << e.what();
  }
  std::ofstream(path, std::ios::app) << "2\n";
  EXPECT_EQ(load_record_config(path).batch, 512);
  std::filesystem::remove(path);
}

TEST(RecordConfig, AMissingFileIsNoInput) {
  try {
    load_record_config("/nonexistent/vehicle.toml");
    FAIL();
  } catch (const core::Error& e) {
    EXPECT_EQ(e.kind(), core::ErrorKind::no_input);
  }
}

}  // namespace
}  // namespace m2mlat::capture
