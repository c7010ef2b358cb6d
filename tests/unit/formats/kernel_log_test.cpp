// The kernel-log importer: single lines (as the live /dev/kmsg capture uses them), dmesg output with
// other messages mixed in, /dev/kmsg records, the lean timestamp scan, and malformed GPIO lines.
#include "m2mlat/formats/kernel_log.hpp"

#include <gtest/gtest.h>

#include "formats_test_support.hpp"
#include "m2mlat/formats/import_file.hpp"
#include "m2mlat/formats/input_text.hpp"

namespace m2mlat::formats {
namespace {

using test::expect_data_error;
using test::fixture;

TEST(KernelLogLine, PlainLine) {
  const KernelLogLine line = parse_kernel_log_line("GPIO_16_IRQ:1762872545550296135\n");
  ASSERT_EQ(line.kind, KernelLineKind::record);
  EXPECT_EQ(line.record.pin, 16u);
  EXPECT_EQ(line.record.time_ns, 1'762'872'545'550'296'135);
  EXPECT_FALSE(line.record.log_time_us.has_value());
  EXPECT_FALSE(line.record.kmsg_seq.has_value());
  EXPECT_EQ(line.pin_text, "16");
}

TEST(KernelLogLine, DmesgPrefixGivesLogTime) {
  const KernelLogLine line = parse_kernel_log_line("[ 1234.567890] GPIO_16_IRQ:1762872545550296135");
  ASSERT_EQ(line.kind, KernelLineKind::record);
  EXPECT_EQ(line.record.time_ns, 1'762'872'545'550'296'135);
  EXPECT_EQ(line.record.log_time_us, 1'234'567'890);
  // dmesg -T: a date in the brackets is no log time, and no error either.
  const KernelLogLine dated = parse_kernel_log_line("[Tue Nov 11 15:42:25 2025] GPIO_17_IRQ:5");
  ASSERT_EQ(dated.kind, KernelLineKind::record);
  EXPECT_EQ(dated.record.pin, 17u);
  EXPECT_EQ(dated.record.time_ns, 5);
  EXPECT_FALSE(dated.record.log_time_us.has_value());
}

TEST(KernelLogLine, KmsgRecordKeepsSequenceNumber) {
  const KernelLogLine line = parse_kernel_log_line("6,1234,5678901,-;GPIO_16_IRQ:1762872545550296135");
  ASSERT_EQ(line.kind, KernelLineKind::record);
  EXPECT_EQ(line.record.kmsg_seq, 1234u);
  EXPECT_EQ(line.record.log_time_us, 5'678'901);
  EXPECT_EQ(line.record.time_ns, 1'762'872'545'550'296'135);
  // Extra kmsg header fields (newer kernels add a caller id) are allowed.
  const KernelLogLine caller = parse_kernel_log_line("6,1235,5678999,-,caller=T42;GPIO_16_IRQ:7");
  ASSERT_EQ(caller.kind, KernelLineKind::record);
  EXPECT_EQ(caller.record.kmsg_seq, 1235u);
}

TEST(KernelLogLine, UnrelatedLines) {
  for (const char* text :
       {"", "[    1.000000] usb 1-1: new device", " SUBSYSTEM=gpio",
        "gpio gpiochip0: GPIO_5 is not an interrupt line", "GPIO_16_IRQ 17", "GPIO_16: 1"}) {
    EXPECT_EQ(parse_kernel_log_line(text).kind, KernelLineKind::unrelated) << text;
  }
}

TEST(KernelLogLine, MalformedLinesSayWhatIsWrong) {
  struct Case {
    const char* line;
    const char* field;
    const char* text;
  };
  for (const Case& c :
       {Case{"GPIO_16_IRQ:12ab", "timestamp", "12ab"}, Case{"GPIO_16_IRQ:", "timestamp", ""},
        Case{"GPIO_16_IRQ:-5", "timestamp", "-5"},
        Case{"GPIO_16_IRQ:99999999999999999999", "timestamp", "99999999999999999999"},
        Case{"GPIO_16_IRQ:1 2", "timestamp", "1 2"}, Case{"GPIO_x_IRQ:1", "pin", "x"},
        Case{"GPIO__IRQ:1", "pin", ""}, Case{"6,12x,5,-;GPIO_16_IRQ:1", "kmsg header", "6,12x,5,-"}}) {
    const KernelLogLine parsed = parse_kernel_log_line(c.line);
    EXPECT_EQ(parsed.kind, KernelLineKind::malformed) << c.line;
    EXPECT_EQ(parsed.field, c.field) << c.line;
    EXPECT_EQ(parsed.text, c.text) << c.line;
    EXPECT_NE(parsed.describe().find(std::string("field ") + c.field), std::string::npos);
  }
}

TEST(KernelLogImport, DmesgWithOtherLinesMixedIn) {
  const ImportedFile file = import_file(fixture("dmesg_mixed.log"), Format::kernel_log, ImportOptions{});
  const auto& imported = std::get<EventImport>(file.content);
  ASSERT_EQ(imported.events.size(), 6u);
  EXPECT_EQ(imported.records, 6u);
  EXPECT_EQ(imported.ignored_lines,
            4u);  // boot, usb, brcmfmac, "GPIO_5 is not..." (the blank is not counted)
  EXPECT_EQ(imported.skipped_lines, 0u);
  const std::int64_t expected[] = {1'700'000'100'100'000'000, 1'700'000'101'600'000'001,
                                   1'700'000'102'500'000'002, 1'700'000'103'000'000'003,
                                   1'700'000'104'000'000'004, 1'700'000'105'250'000'005};
  for (std::size_t i = 0; i < 6; ++i) {
    const core::Event& event = imported.events[i];
    EXPECT_EQ(event.time, core::TimePoint::from_ns(core::Clock::realtime, expected[i]));
    EXPECT_EQ(event.node, "local");
    EXPECT_EQ(event.channel, i == 2 ? "gpio17" : "gpio16");
    EXPECT_EQ(event.edge, core::Edge::falling);
    EXPECT_EQ(event.seqno, 0u);
    EXPECT_EQ(event.flags, core::kFlagImported | core::kFlagNoKernelSeqno);
  }
  ASSERT_EQ(imported.kernel_records.size(), 6u);
  EXPECT_EQ(imported.kernel_records[0].log_time_us, 1'234'567'890);
  EXPECT_FALSE(imported.kernel_records[3].log_time_us.has_value());  // plain line
  EXPECT_FALSE(imported.kernel_records[4].log_time_us.has_value());  // dmesg -T
  EXPECT_EQ(imported.kernel_records[5].log_time_us, 1'240'250'000);  // kern.log
}

TEST(KernelLogImport, NodeChannelAndPinFilter) {
  const InputText input = InputText::read_file(fixture("dmesg_mixed.log"));
  ImportOptions options;
  options.node = "vehicle";
  options.channel = "wheel";
  options.only_line = "16";
  const EventImport imported = import_kernel_log(input.text(), input.name(), options);
  ASSERT_EQ(imported.events.size(), 5u);
  EXPECT_EQ(imported.skipped_lines, 1u);
  for (const core::Event& event : imported.events) {
    EXPECT_EQ(event.node, "vehicle");
    EXPECT_EQ(event.channel, "wheel");
  }
  // One channel for a file with two pins and no filter would mix them: an error at the second pin.
  options.only_line.clear();
  expect_data_error([&] { import_kernel_log(input.text(), input.name(), options); },
                    {"dmesg_mixed.log:6:", "field pin", "'17'", "line 3"});
  // A filter that matches nothing.
  options.only_line = "21";
  options.channel.clear();
  expect_data_error([&] { import_kernel_log(input.text(), input.name(), options); }, {"pin 21"});
}

TEST(KernelLogImport, KmsgRecords) {
  const InputText input = InputText::read_file(fixture("kmsg_records.log"));
  const EventImport imported = import_kernel_log(input.text(), input.name(), ImportOptions{});
  ASSERT_EQ(imported.events.size(), 3u);
  EXPECT_EQ(imported.ignored_lines, 3u);  // the usb record and its two continuation lines
  EXPECT_EQ(imported.kernel_records[0].kmsg_seq, 1021u);
  EXPECT_EQ(imported.kernel_records[1].kmsg_seq, 1023u);
  EXPECT_EQ(imported.kernel_records[2].kmsg_seq, 1024u);
  EXPECT_EQ(imported.kernel_records[2].log_time_us, 1'236'067'999);
  EXPECT_EQ(imported.events[2].time.ns(), 1'700'000'102'600'000'002);
}

TEST(KernelLogImport, MalformedGpioLineNamesFileAndLine) {
  expect_data_error([] { import_file(fixture("dmesg_bad_timestamp.log"), std::nullopt, ImportOptions{}); },
                    {"dmesg_bad_timestamp.log:4: field timestamp: '12ab' is not an integer"});
}

TEST(KernelLogImport, EmptyOrWithoutRecords) {
  expect_data_error([] { import_kernel_log("", "empty.log", ImportOptions{}); }, {"empty.log: is empty"});
  expect_data_error([] { import_kernel_log("[ 1.0] usb 1-1: new device\n", "boot.log", ImportOptions{}); },
                    {"boot.log:", "no GPIO_<pin>_IRQ:<ns> lines", "1 other"});
}

TEST(KernelLogImport, CrlfBomAndNoFinalNewline) {
  const EventImport imported =
      import_kernel_log("\xEF\xBB\xBFGPIO_16_IRQ:10\r\n\r\nGPIO_16_IRQ:11", "crlf.log", ImportOptions{});
  ASSERT_EQ(imported.events.size(), 2u);
  EXPECT_EQ(imported.events[0].time.ns(), 10);
  EXPECT_EQ(imported.events[1].time.ns(), 11);
}

TEST(KernelLogScan, LeanTimestampsPerPin) {
  const InputText input = InputText::read_file(fixture("dmesg_mixed.log"));
  const auto series = scan_kernel_log_timestamps(input.text(), input.name());
  ASSERT_EQ(series.size(), 2u);
  EXPECT_EQ(series[0].label, "16");
  EXPECT_EQ(series[0].ns.size(), 5u);
  EXPECT_EQ(series[1].label, "17");
  ASSERT_EQ(series[1].ns.size(), 1u);
  EXPECT_EQ(series[1].ns[0], 1'700'000'102'500'000'002);
  const auto only = scan_kernel_log_timestamps(input.text(), input.name(), "17");
  ASSERT_EQ(only.size(), 1u);
  EXPECT_EQ(only[0].label, "17");
  // The lean path gives the same times as the full import.
  const EventImport full = import_kernel_log(input.text(), input.name(), ImportOptions{});
  std::vector<std::int64_t> pin16;
  for (const core::Event& event : full.events)
    if (event.channel == "gpio16") pin16.push_back(event.time.ns());
  EXPECT_EQ(series[0].ns, pin16);
  expect_data_error([&] { scan_kernel_log_timestamps("GPIO_16_IRQ:1\nGPIO_16_IRQ:x1\n", "k.log"); },
                    {"k.log:2: field timestamp"});
}

}  // namespace
}  // namespace m2mlat::formats
