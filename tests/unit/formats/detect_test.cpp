// Format names, detection by content, and import/export through files by name.
#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <fstream>

#include "formats_test_support.hpp"
#include "m2mlat/formats/format.hpp"
#include "m2mlat/formats/import_file.hpp"
#include "m2mlat/formats/input_text.hpp"
#include "temp_dir.hpp"

namespace m2mlat::formats {
namespace {

using test::expect_data_error;
using test::fixture;

Format detected(const std::string& file) {
  const InputText input = InputText::read_file(fixture(file));
  return require_format(input.text(), input.name());
}

TEST(FormatNames, RoundTripAndUnknown) {
  for (const Format format : kAllFormats) EXPECT_EQ(parse_format(to_string(format)), format);
  try {
    parse_format("xml");
    ADD_FAILURE() << "no error";
  } catch (const core::Error& e) {
    EXPECT_EQ(e.kind(), core::ErrorKind::usage);
    EXPECT_NE(std::string(e.what()).find("kernel-log"), std::string::npos);
  }
  EXPECT_EQ(content_of(Format::rig_paired_csv), Content::pairs);
  EXPECT_EQ(content_of(Format::rig_sync_csv), Content::sync_samples);
  EXPECT_EQ(content_of(Format::kernel_log), Content::events);
  EXPECT_FALSE(is_importable(Format::pairs_csv));
}

TEST(Detect, EveryFixture) {
  EXPECT_EQ(detected("dmesg_mixed.log"), Format::kernel_log);
  EXPECT_EQ(detected("kmsg_records.log"), Format::kernel_log);
  EXPECT_EQ(detected("dmesg_bad_timestamp.log"), Format::kernel_log);  // detected; the import then fails
  EXPECT_EQ(detected("rig_export_two_pins.csv"), Format::rig_export_csv);
  EXPECT_EQ(detected("rig_paired_small.csv"), Format::rig_paired_csv);
  EXPECT_EQ(detected("rig_paired_bom_crlf.csv"), Format::rig_paired_csv);
  EXPECT_EQ(detected("rig_sync_small.csv"), Format::rig_sync_csv);
  EXPECT_EQ(detected("events_small.csv"), Format::events_csv);
  EXPECT_EQ(detected("events_time_s.csv"), Format::events_csv);
  EXPECT_EQ(detected("events_small.jsonl"), Format::events_jsonl);
}

TEST(Detect, FromText) {
  EXPECT_EQ(detect_format("\n\nGPIO_16_IRQ:1\n"), Format::kernel_log);
  EXPECT_EQ(detect_format("[ 1.0] boot\n[ 2.0] usb\n[ 3.0] GPIO_4_IRQ:1\n"), Format::kernel_log);
  EXPECT_EQ(detect_format("# format: m2mlat-pairs/1\ncause_node\n"), Format::pairs_csv);
  EXPECT_EQ(detect_format("{\"format\":\"m2mlat-pairs/1\"}\n"), Format::pairs_jsonl);
  EXPECT_EQ(detect_format("# a comment\nnode,channel,time_ns\n"), Format::events_csv);
  EXPECT_EQ(detect_format("\xEF\xBB\xBFLine,Seconds,Nanoseconds\r\n"), Format::rig_export_csv);
  EXPECT_EQ(detect_format("[ 1.0] usb 1-1: new device\n"), std::nullopt);
  EXPECT_EQ(detect_format("{\"a\":1}\n"), std::nullopt);
  EXPECT_EQ(detect_format("Line,Seconds\n"), std::nullopt);
  EXPECT_EQ(detect_format(""), std::nullopt);
  expect_data_error([] { require_format("a,b,c\n1,2,3\n", "what.csv"); },
                    {"what.csv:1: cannot tell the format from 'a,b,c'", "rig-paired-csv"});
  expect_data_error([] { require_format("\n\n", "blank.txt"); }, {"blank.txt: is empty"});
}

TEST(ImportFile, ErrorsOfFilesAndFormats) {
  try {
    import_file(fixture("no_such_file.csv"), std::nullopt, {});
    ADD_FAILURE() << "no error";
  } catch (const core::Error& e) {
    EXPECT_EQ(e.kind(), core::ErrorKind::no_input);
    EXPECT_NE(std::string(e.what()).find("no_such_file.csv"), std::string::npos);
  }
  // An explicit format is used as given: a paired CSV is no kernel log.
  expect_data_error([] { import_file(fixture("rig_paired_small.csv"), Format::kernel_log, {}); },
                    {"rig_paired_small.csv:", "no GPIO_<pin>_IRQ:<ns> lines"});
  try {
    import_text("# format: m2mlat-pairs/1\ncause_node\n", "pairs.csv", std::nullopt, {});
    ADD_FAILURE() << "no error";
  } catch (const core::Error& e) {
    EXPECT_EQ(e.kind(), core::ErrorKind::usage);
  }
}

TEST(ImportFile, LeanTimestamps) {
  const auto kernel = read_timestamps(fixture("dmesg_mixed.log"), std::nullopt);
  ASSERT_EQ(kernel.size(), 2u);
  EXPECT_EQ(kernel[0].ns.size(), 5u);
  const auto exported = read_timestamps(fixture("rig_export_two_pins.csv"), std::nullopt, "17");
  ASSERT_EQ(exported.size(), 1u);
  EXPECT_EQ(exported[0].ns,
            (std::vector<std::int64_t>{1'700'000'100'950'123'456, 1'700'000'104'812'000'001}));
  const auto paired = read_timestamps(fixture("rig_paired_small.csv"), std::nullopt);
  ASSERT_EQ(paired.size(), 2u);
  EXPECT_EQ(paired[0].label, "operator/wheel");
  EXPECT_EQ(paired[1].label, "vehicle/wheel");
  EXPECT_EQ(paired[1].ns[0], 1'700'000'100'950'123'456);
  const auto events = read_timestamps(fixture("events_small.jsonl"), std::nullopt);
  ASSERT_EQ(events.size(), 2u);
  EXPECT_EQ(events[1].ns.size(), 2u);
  EXPECT_THROW(read_timestamps(fixture("rig_sync_small.csv"), std::nullopt), core::Error);
}

TEST(ExportFile, EventsAndPairsThroughFilesOneNanosecondApart) {
  const m2mlat::testing::TempDir temp;
  const auto& dir = temp.path();
  const std::int64_t t = 1'762'872'545'550'296'135;  // beyond double precision: 1 ns steps are lost there
  std::vector<core::Event> events;
  for (std::int64_t i = 0; i < 3; ++i)
    events.push_back(core::Event{"operator", "wheel", core::Edge::falling,
                                 core::TimePoint::from_ns(core::Clock::realtime, t + i),
                                 static_cast<std::uint64_t>(i + 1), static_cast<std::uint64_t>(i + 1), 0});
  for (const Format format : {Format::events_csv, Format::events_jsonl}) {
    const std::string path = (dir / ("events." + std::string(to_string(format)))).string();
    export_events(path, format, events);
    EXPECT_FALSE(std::filesystem::exists(path + ".tmp"));
    const ImportedFile back = import_file(path, std::nullopt, {});  // detected
    EXPECT_EQ(back.format, format);
    EXPECT_EQ(std::get<EventImport>(back.content).events, events);
  }
  const std::vector<PairRow> pairs{{0, 0, events[0].time, events[1].time}};
  const std::string rig = (dir / "pairs_rig.csv").string();
  export_pairs(rig, Format::rig_paired_csv, pairs);
  const ImportedFile back = import_file(rig, std::nullopt, {});
  EXPECT_EQ(back.format, Format::rig_paired_csv);
  EXPECT_EQ(std::get<PairedImport>(back.content).pairs[0].latency(), core::Duration{1});
  EXPECT_THROW(export_events((dir / "x").string(), Format::kernel_log, events), core::Error);
  EXPECT_THROW(export_pairs((dir / "y").string(), Format::events_csv, pairs), core::Error);
}

}  // namespace
}  // namespace m2mlat::formats
