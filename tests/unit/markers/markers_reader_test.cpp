// m2mlat-markers/1 read back: what the writer wrote, and bad rows named by file, line and field.
#include "m2mlat/markers/markers_reader.hpp"

#include <gtest/gtest.h>

#include "m2mlat/core/error.hpp"
#include "m2mlat/markers/markers_file.hpp"

using namespace m2mlat;
using namespace m2mlat::markers;

namespace m2mlat::markers::markers_reader_test {

std::string read_error_of(const std::string& text) {
  try {
    parse_markers_csv(text, "m.csv");
  } catch (const core::Error& e) {
    EXPECT_EQ(e.kind(), core::ErrorKind::data);
    return e.what();
  }
  ADD_FAILURE() << "no error for: " << text;
  return {};
}

TEST(MarkersReader, ReadsWhatTheWriterWrote) {
  std::vector<Marker> written(2);
  written[0].node = "operator";
  written[0].name = "send";
  written[0].time = core::TimePoint::from_ns(core::Clock::realtime, 1'780'304'400'123'456'789);
  written[0].source = StampSource::host;
  written[0].key = "a,\"b\"";  // quoted in the file
  written[0].sender_time = core::TimePoint::from_ns(core::Clock::realtime, 1'780'304'400'122'000'000);
  written[0].origin = "op.pcap#4 tcp 10.0.0.1:5>10.0.1.2:7000";
  written[1].node = "vehicle";
  written[1].name = "apply";
  written[1].time = core::TimePoint::from_ns(core::Clock::realtime, -5);
  written[1].source = StampSource::adapter;
  const auto read = parse_markers_csv(markers_csv(written), "m.csv");
  ASSERT_EQ(read.size(), 2u);
  for (std::size_t i = 0; i < 2; ++i) {
    EXPECT_EQ(read[i].node, written[i].node);
    EXPECT_EQ(read[i].name, written[i].name);
    EXPECT_EQ(read[i].time, written[i].time);
    EXPECT_EQ(read[i].source, written[i].source);
    EXPECT_EQ(read[i].key, written[i].key);
    EXPECT_EQ(read[i].sender_time, written[i].sender_time);
    EXPECT_EQ(read[i].origin, written[i].origin);
  }
}

// Files before the header-first layout had a "# format:" line first: both read the same.
TEST(MarkersReader, ReadsTheHeaderFirstAndTheOlderFormatLine) {
  const std::string header = "node,name,clock,time_ns,source,key,sender_ns,sender_to_capture_ns,origin\n";
  const std::string row = "operator,send,realtime,12,kernel,7,,,udp 127.0.0.1:4000\n";
  const auto plain = parse_markers_csv(header + row, "m.csv");
  const auto older = parse_markers_csv("# format: m2mlat-markers/1\n" + header + row, "m.csv");
  ASSERT_EQ(plain.size(), 1u);
  ASSERT_EQ(older.size(), 1u);
  EXPECT_EQ(plain[0].time.ns(), 12);
  EXPECT_EQ(plain[0].source, StampSource::kernel);
  EXPECT_EQ(older[0].time.ns(), plain[0].time.ns());
  EXPECT_EQ(older[0].key, plain[0].key);
}

TEST(MarkersReader, BadRowsNameTheFileTheLineAndTheField) {
  const std::string head =
      "# format: m2mlat-markers/1\nnode,name,clock,time_ns,source,key,sender_ns,sender_to_capture_ns,origin\n";
  EXPECT_NE(read_error_of(head + "operator,send,realtime,12x,host,1,,,sim\n").find("m.csv:3: field time_ns"),
            std::string::npos);
  EXPECT_NE(read_error_of(head + "operator,send,monotonic,12,host,1,,,sim\n").find("m.csv:3: field clock"),
            std::string::npos);
  EXPECT_NE(read_error_of(head + "operator,send,realtime,12,gps,1,,,sim\n").find("m.csv:3: field source"),
            std::string::npos);
  EXPECT_NE(read_error_of(head + ",send,realtime,12,host,1,,,sim\n").find("m.csv:3: field node"), std::string::npos);
  EXPECT_NE(read_error_of(head + "operator,send,realtime,12,host,1,10,3,sim\n")
                .find("m.csv:3: field sender_to_capture_ns"),
            std::string::npos);
  EXPECT_NE(read_error_of(head + "operator,send,realtime,12\n").find("m.csv:3: 4 fields, expected 9"),
            std::string::npos);
  EXPECT_NE(read_error_of("node,name\n").find("m.csv:1: header"), std::string::npos);
  EXPECT_NE(read_error_of("# format: m2mlat-oneway/1\n").find("m.csv:1: format"), std::string::npos);
  EXPECT_NE(read_error_of("").find("no header"), std::string::npos);
}

}  // namespace m2mlat::markers::markers_reader_test
