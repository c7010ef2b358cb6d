// The gyroscope trace file (m2mlat-gyro/1): written then read back unchanged, and every kind of
// malformed input refused with its file, line and field.
#include "m2mlat/formats/rate_trace_csv.hpp"

#include <gtest/gtest.h>

#include <sstream>

#include "m2mlat/core/error.hpp"

namespace m2mlat::formats::rate_trace_csv_test {
namespace {

std::string error_of(const std::string& text) {
  try {
    read_rate_trace_csv(text, "g.csv");
  } catch (const core::Error& e) {
    EXPECT_EQ(e.kind(), core::ErrorKind::data);
    return e.what();
  }
  return "no error";
}

TEST(RateTraceCsv, WriteThenReadGivesTheSameTrace) {
  core::RateTrace trace;
  trace.clock = core::Clock::realtime;
  trace.counts_per_deg_s = 131;
  trace.samples = {{1764086400000512345, 48211, {12, -3, 0}},
                   {1764086400001512345, 0, {-32768, 32767, 131}},
                   {1764086400001512345, 2147483647, {0, 0, -1}}};
  std::ostringstream out;
  write_rate_trace_csv(out, trace, {"source: mpu6050 /dev/i2c-1 address 0x68"});
  EXPECT_TRUE(
      out.str().starts_with("# format: m2mlat-gyro/1\n# clock: realtime\n# counts_per_deg_s: 131\n"
                            "# source: mpu6050 /dev/i2c-1 address 0x68\ntime_ns,bound_ns,x,y,z\n"))
      << out.str();
  const auto back = read_rate_trace_csv(out.str(), "g.csv");
  EXPECT_EQ(back.clock, trace.clock);
  EXPECT_EQ(back.counts_per_deg_s, 131.0);
  ASSERT_EQ(back.samples.size(), 3u);
  for (std::size_t i = 0; i < 3; ++i) {
    EXPECT_EQ(back.samples[i].time_ns, trace.samples[i].time_ns);
    EXPECT_EQ(back.samples[i].bound_ns, trace.samples[i].bound_ns);
    EXPECT_EQ(back.samples[i].raw, trace.samples[i].raw);
  }
}

TEST(RateTraceCsv, MalformedInputIsRefusedNamingFileLineAndField) {
  const std::string head =
      "# format: m2mlat-gyro/1\n# clock: realtime\n# counts_per_deg_s: 131\ntime_ns,bound_ns,x,y,z\n";
  EXPECT_NE(error_of("time_ns,bound_ns,x,y,z\n").find("g.csv:1: expected the line '# format: m2mlat-gyro/1'"),
            std::string::npos);
  EXPECT_NE(error_of("# format: m2mlat-gyro/2\n").find("g.csv:1:"), std::string::npos);
  EXPECT_NE(error_of("# format: m2mlat-gyro/1\n# clock: sundial\n").find("g.csv:2: field clock"),
            std::string::npos);
  EXPECT_NE(
      error_of("# format: m2mlat-gyro/1\n# counts_per_deg_s: -3\n").find("g.csv:2: field counts_per_deg_s"),
      std::string::npos);
  EXPECT_NE(error_of("# format: m2mlat-gyro/1\ntime,x\n").find("g.csv:2: expected the header"),
            std::string::npos);
  EXPECT_NE(error_of("# format: m2mlat-gyro/1\n").find("no header line"), std::string::npos);
  EXPECT_NE(error_of(head + "1,2,3,4\n").find("g.csv:5: expected 5 fields"), std::string::npos);
  EXPECT_NE(error_of(head + "1,2,3,4,32768\n").find("g.csv:5: field z: '32768' is out of range"),
            std::string::npos);
  EXPECT_NE(error_of(head + "1,-1,3,4,5\n").find("g.csv:5: field bound_ns"), std::string::npos);
  EXPECT_NE(error_of(head + "1.5,1,3,4,5\n").find("g.csv:5: field time_ns: '1.5' is not an integer"),
            std::string::npos);
  EXPECT_NE(
      error_of(head + "10,1,3,4,5\n9,1,3,4,5\n").find("g.csv:6: field time_ns: '9' is before the previous"),
      std::string::npos);
  // A file cut mid-write: the last line has no line end.
  EXPECT_NE(error_of(head + "10,1,3,4,5\n11,1,3").find("g.csv:6:"), std::string::npos);
}

}  // namespace
}  // namespace m2mlat::formats::rate_trace_csv_test
