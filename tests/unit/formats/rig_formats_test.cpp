// The reference rig's three CSV files: export (Line,Seconds,Nanoseconds), paired results (with the
// check of its own m2m_latency_ms column) and sync tests; and the paired layout written back.
#include <gtest/gtest.h>

#include <sstream>

#include "formats_test_support.hpp"
#include "m2mlat/formats/import_file.hpp"
#include "m2mlat/formats/input_text.hpp"
#include "m2mlat/formats/rig_export.hpp"
#include "m2mlat/formats/rig_paired.hpp"
#include "m2mlat/formats/rig_sync.hpp"

namespace m2mlat::formats {
namespace {

using test::expect_data_error;
using test::fixture;

constexpr std::string_view kPairedHeader =
    "remote_station_s,remote_station_ns,vehicle_s,vehicle_ns,,m2m_latency_ms\n";
constexpr std::string_view kSyncHeader =
    "trigger_time_s,sync_offset_ns,Jitter_ns,,sync_offset_ms,Jitter_ms\n";

// m2m_latency_ms of the fixture parsed independently: integer part and up to 6 decimals, padded.
std::int64_t ms_text_to_ns(const std::string& text) {
  const auto dot = text.find('.');
  std::string whole = text.substr(0, dot);
  std::string frac = dot == std::string::npos ? "" : text.substr(dot + 1);
  frac.resize(6, '0');
  return std::stoll(whole) * 1'000'000 + std::stoll(frac);
}

TEST(RigExport, TwoPinsBecomeTwoChannels) {
  ImportOptions options;
  options.node = "operator";
  const auto file = import_file(fixture("rig_export_two_pins.csv"), std::nullopt, options);
  EXPECT_EQ(file.format, Format::rig_export_csv);
  const auto& imported = std::get<EventImport>(file.content);
  ASSERT_EQ(imported.events.size(), 4u);
  EXPECT_EQ(imported.events[0].channel, "gpio16");
  EXPECT_EQ(imported.events[1].channel, "gpio17");
  EXPECT_EQ(imported.events[1].time,
            core::TimePoint::from_ns(core::Clock::realtime, 1'700'000'100'950'123'456));
  EXPECT_EQ(imported.events[2].time.ns(), 1'700'000'103'999'999'999);
  EXPECT_EQ(imported.events[3].node, "operator");
  EXPECT_EQ(imported.events[3].flags, core::kFlagImported | core::kFlagNoKernelSeqno);
}

TEST(RigExport, LabelsFilterAndLeanScan) {
  const std::string text = "Line,Seconds,Nanoseconds\nwheel,10,5\nbrake,11,6\nwheel,12,0\n";
  ImportOptions options;
  options.only_line = "wheel";
  const EventImport imported = import_rig_export_csv(text, "labels.csv", options);
  ASSERT_EQ(imported.events.size(), 2u);
  EXPECT_EQ(imported.skipped_lines, 1u);
  EXPECT_EQ(imported.events[0].channel, "wheel");
  EXPECT_EQ(imported.events[1].time.ns(), 12'000'000'000);
  const auto series = scan_rig_export_timestamps(text, "labels.csv");
  ASSERT_EQ(series.size(), 2u);
  EXPECT_EQ(series[0].label, "wheel");
  EXPECT_EQ(series[0].ns, (std::vector<std::int64_t>{10'000'000'005, 12'000'000'000}));
  EXPECT_EQ(series[1].ns, (std::vector<std::int64_t>{11'000'000'006}));
}

// The rig's export.sh: Line counts the rows, the pin is in the file's name.
TEST(RigExport, ARowCounterIsOnePinTheFilesName) {
  const std::string text = "Line,Seconds,Nanoseconds\n0,10,5\n1,11,6\n2,12,0\n";
  ImportOptions options;
  options.node = "vehicle";
  const EventImport imported = import_rig_export_csv(text, "runs/Static_5G_measuremest_16.csv", options);
  ASSERT_EQ(imported.events.size(), 3u);
  for (const auto& e : imported.events) EXPECT_EQ(e.channel, "gpio16");
  EXPECT_EQ(imported.events[2].time.ns(), 12'000'000'000);
  EXPECT_EQ(import_rig_export_csv(text, "edges.csv", options).events[0].channel, "line");
  const auto series = scan_rig_export_timestamps(text, "a_measurement_23.csv");
  ASSERT_EQ(series.size(), 1u);
  EXPECT_EQ(series[0].label, "23");
  EXPECT_EQ(series[0].ns.size(), 3u);
  // Counting from 1 is a counter too; a pin that repeats, or a count that skips, is not.
  EXPECT_EQ(rig_export_line_label("Line,Seconds,Nanoseconds\n1,1,0\n2,2,0\n", "x_measuremest_5.csv"), "5");
  EXPECT_EQ(rig_export_line_label("Line,Seconds,Nanoseconds\n0,1,0\n2,2,0\n", "x_measuremest_5.csv"), "");
  EXPECT_EQ(rig_export_line_label("Line,Seconds,Nanoseconds\n16,1,0\n16,2,0\n", "x_measuremest_5.csv"), "");
}

TEST(RigExport, MalformedRows) {
  const std::string header = "Line,Seconds,Nanoseconds\n";
  expect_data_error([&] { import_rig_export_csv(header + "16,1,1000000000\n", "e.csv", {}); },
                    {"e.csv:2: field Nanoseconds: '1000000000' is out of range [0, 999999999]"});
  expect_data_error([&] { import_rig_export_csv(header + "16,1,-1\n", "e.csv", {}); },
                    {"e.csv:2: field Nanoseconds: '-1' is out of range"});
  expect_data_error([&] { import_rig_export_csv(header + "16,1,2\n16,1.5,2\n", "e.csv", {}); },
                    {"e.csv:3: field Seconds: '1.5' is not an integer"});
  expect_data_error([&] { import_rig_export_csv(header + "16,1,2,3\n", "e.csv", {}); },
                    {"e.csv:2: expected 3 fields (Line,Seconds,Nanoseconds), found 4"});
  expect_data_error([&] { import_rig_export_csv(header + ",1,2\n", "e.csv", {}); }, {"e.csv:2: field Line"});
  expect_data_error([&] { import_rig_export_csv(header + "16,9999999999,0\n", "e.csv", {}); },
                    {"e.csv:2: field Seconds", "overflows"});
  expect_data_error([] { import_file(fixture("rig_export_concatenated.csv"), std::nullopt, {}); },
                    {"rig_export_concatenated.csv:4: the header appears again"});
  expect_data_error([] { import_rig_export_csv("16,1,2\n", "e.csv", {}); }, {"e.csv:1: missing header"});
  expect_data_error([] { import_rig_export_csv("Pin,Seconds,Nanoseconds\n", "e.csv", {}); },
                    {"e.csv:1: header is 'Pin,Seconds,Nanoseconds', expected 'Line,Seconds,Nanoseconds'"});
  expect_data_error([] { import_rig_export_csv("\n\n", "e.csv", {}); }, {"e.csv: is empty"});
  // A header alone, and trailing blank lines, are fine.
  EXPECT_TRUE(import_rig_export_csv(header + "\n\n", "e.csv", {}).events.empty());
}

TEST(RigPaired, LatenciesEqualTheFilesOwnColumnToOneMicrosecond) {
  const auto file = import_file(fixture("rig_paired_small.csv"), std::nullopt, ImportOptions{});
  EXPECT_EQ(file.format, Format::rig_paired_csv);
  const auto& paired = std::get<PairedImport>(file.content);
  ASSERT_EQ(paired.pairs.size(), 6u);
  ASSERT_EQ(paired.causes.size(), 6u);
  ASSERT_EQ(paired.effects.size(), 6u);
  ASSERT_EQ(paired.checks.size(), 6u);
  const std::string file_ms[] = {"850.123456", "812.000002", "850.4", "700", "901.5", "876.54321"};
  for (std::size_t i = 0; i < 6; ++i) {
    const PairRow& pair = paired.pairs[i];
    EXPECT_EQ(pair.cause_index, static_cast<std::int64_t>(i));
    EXPECT_EQ(pair.cause_time, paired.causes[i].time);
    EXPECT_EQ(pair.effect_time, paired.effects[i].time);
    EXPECT_EQ(paired.checks[i].file_latency.count(), ms_text_to_ns(file_ms[i]));
    EXPECT_EQ(paired.checks[i].line, static_cast<long>(i + 2));
    const std::int64_t diff = pair.latency().count() - ms_text_to_ns(file_ms[i]);
    EXPECT_EQ(paired.checks[i].difference.count(), diff);
    if (i != 4) {
      EXPECT_LE(std::abs(diff), 1000) << "row " << i;
      EXPECT_TRUE(paired.checks[i].agrees);
    }
  }
  EXPECT_EQ(paired.pairs[0].latency().count(), 850'123'456);
  EXPECT_EQ(paired.pairs[1].latency().count(), 812'000'002);  // borrows across the second
  EXPECT_EQ(paired.checks[2].difference.count(), 400);        // file rounded to 0.1 ms here
  EXPECT_EQ(paired.checks[5].difference.count(), 1);
  // Row 5 (line 6) says 901.5 ms where the timestamps say 900 ms: a warning, not an error.
  EXPECT_FALSE(paired.checks[4].agrees);
  EXPECT_EQ(paired.checks[4].difference.count(), -1'500'000);
  EXPECT_EQ(paired.disagreements, (std::vector<std::size_t>{4}));
  EXPECT_EQ(paired.causes[0].node, "operator");
  EXPECT_EQ(paired.effects[0].node, "vehicle");
  EXPECT_EQ(paired.effects[0].channel, "wheel");
  EXPECT_EQ(paired.causes[0].time.clock(), core::Clock::realtime);
}

TEST(RigPaired, BomAndCrlfAccepted) {
  const auto file = import_file(fixture("rig_paired_bom_crlf.csv"), std::nullopt, ImportOptions{});
  EXPECT_EQ(file.format, Format::rig_paired_csv);
  const auto& paired = std::get<PairedImport>(file.content);
  ASSERT_EQ(paired.pairs.size(), 2u);
  EXPECT_TRUE(paired.disagreements.empty());
  EXPECT_EQ(paired.pairs[1].latency().count(), 812'000'002);
}

TEST(RigPaired, MalformedRows) {
  expect_data_error([] { import_file(fixture("rig_paired_bad_ns.csv"), std::nullopt, ImportOptions{}); },
                    {"rig_paired_bad_ns.csv:3: field remote_station_ns: '99999999x' is not an integer"});
  const std::string header(kPairedHeader);
  expect_data_error([&] { import_rig_paired_csv(header + "1,0,1,5,x,0.000005\n", "p.csv", {}); },
                    {"p.csv:2: field 5 (unnamed): 'x' should be empty"});
  expect_data_error([&] { import_rig_paired_csv(header + "1,0,1,5,,0.0000051\n", "p.csv", {}); },
                    {"p.csv:2: field m2m_latency_ms: '0.0000051' is not a decimal number of milliseconds"});
  expect_data_error([&] { import_rig_paired_csv(header + "1,0,1,5,,1e-6\n", "p.csv", {}); },
                    {"p.csv:2: field m2m_latency_ms"});
  expect_data_error([&] { import_rig_paired_csv(header + "1,0,1,12x,,1\n", "p.csv", {}); },
                    {"p.csv:2: field vehicle_ns: '12x' is not an integer"});
  expect_data_error([&] { import_rig_paired_csv(header + "1,0,1,5\n", "p.csv", {}); },
                    {"p.csv:2: expected 6 fields", "found 4"});
}

TEST(RigPaired, ExportInTheRigsLayoutReadsBack) {
  const auto at = [](std::int64_t ns) { return core::TimePoint::from_ns(core::Clock::realtime, ns); };
  const std::vector<PairRow> pairs{{0, 0, at(1'700'000'100'100'000'000), at(1'700'000'100'950'123'457)},
                                         {1, 1, at(1'700'000'103'999'999'999), at(1'700'000'104'812'000'001)},
                                         {2, 2, at(-1), at(5)}};
  std::ostringstream out;
  write_rig_paired_csv(out, pairs);
  EXPECT_EQ(out.str(), std::string(kPairedHeader) +
                           "1700000100,100000000,1700000100,950123457,,850.123457\n"
                           "1700000103,999999999,1700000104,812000001,,812.000002\n"
                           "-1,999999999,0,5,,0.000006\n");
  const PairedImport back = import_rig_paired_csv(out.str(), "back.csv", {});
  ASSERT_EQ(back.pairs.size(), 3u);
  for (std::size_t i = 0; i < 3; ++i) {
    EXPECT_EQ(back.pairs[i].cause_time, pairs[i].cause_time);
    EXPECT_EQ(back.pairs[i].effect_time, pairs[i].effect_time);
    EXPECT_EQ(back.checks[i].difference.count(), 0);
  }
}

TEST(RigSync, SamplesKeptExactly) {
  const auto file = import_file(fixture("rig_sync_small.csv"), std::nullopt, ImportOptions{});
  EXPECT_EQ(file.format, Format::rig_sync_csv);
  const auto& sync = std::get<SyncImport>(file.content);
  ASSERT_EQ(sync.samples.size(), 4u);
  EXPECT_EQ(sync.samples[0], (SyncSample{2, core::Duration{0}, -512'000, -512'000}));
  EXPECT_EQ(sync.samples[1], (SyncSample{3, core::Duration{1'070'000'000}, -512'256, -256}));
  EXPECT_EQ(sync.samples[2].trigger_time.count(), 2'141'000'000);
  EXPECT_EQ(sync.samples[3].offset_ns, 2560);
  EXPECT_EQ(sync.samples[3].jitter_ns, 513'280);
  for (const SyncSample& s : sync.samples) EXPECT_EQ(s.offset_ns % 256, 0);  // the rig's double parsing shows
}

TEST(RigSync, MalformedRows) {
  const std::string header(kSyncHeader);
  expect_data_error([&] { import_rig_sync_csv(header + "1.0000000001,0,0,,0,0\n", "s.csv"); },
                    {"s.csv:2: field trigger_time_s", "at most 9 decimals"});
  expect_data_error([&] { import_rig_sync_csv(header + "1,256.0,0,,0,0\n", "s.csv"); },
                    {"s.csv:2: field sync_offset_ns: '256.0' is not an integer"});
  expect_data_error([&] { import_rig_sync_csv(header + "1,256,0,,abc,0\n", "s.csv"); },
                    {"s.csv:2: field sync_offset_ms: 'abc'"});
  expect_data_error([&] { import_rig_sync_csv(header + "1,256,0,,0.000256\n", "s.csv"); },
                    {"s.csv:2: expected 6 fields"});
  expect_data_error([&] { import_rig_sync_csv("", "s.csv"); }, {"s.csv: is empty"});
}

}  // namespace
}  // namespace m2mlat::formats
