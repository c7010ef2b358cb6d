// The clock records of the events files and chronyd's step messages: round trips through both
// events formats, old files and unrelated readers, malformed records, the chrony log's lines.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>
#include <fstream>
#include <sstream>

#include "formats_test_support.hpp"
#include "m2mlat/formats/chrony_log.hpp"
#include "m2mlat/formats/events_csv.hpp"
#include "m2mlat/formats/events_jsonl.hpp"
#include "m2mlat/formats/import_file.hpp"

namespace m2mlat::formats::clock_records_test {

using test::expect_data_error;

const std::vector<core::Event> kEvents{
    {"vehicle", "wheel", core::Edge::falling, core::TimePoint::from_ns(core::Clock::realtime, 1'780'304'400'000'000'001), 1, 1, 0}};

std::vector<ClockRecord> records() {
  return {{"vehicle", core::Clock::realtime, 1'780'304'400'000'000'000, "sim", -207'426, 21'952'000, 7'317'333,
           true, R"({"true_error_ns":200000})"},
          {"vehicle", core::Clock::realtime, 1'780'304'520'039'837'641, "step", 40'000'000, 0, 0, false,
           R"({"earliest_ns":1780304520039837641,"origin":"sim","size_known":true,"step_ns":40000000})"}};
}

TEST(ClockRecords, RoundTripThroughBothEventsFormats) {
  for (const auto format : {Format::events_csv, Format::events_jsonl}) {
    std::ostringstream out;
    const auto clocks = records();
    const EventExportOptions options{.clocks = clocks, .origins = {}, .with_meta = true};
    if (format == Format::events_csv)
      write_events_csv(out, kEvents, options);
    else
      write_events_jsonl(out, kEvents, options);
    const auto file = import_text(out.str(), "x", std::nullopt, {});  // detected, not told
    EXPECT_EQ(file.format, format);
    const auto& imported = std::get<EventImport>(file.content);
    EXPECT_EQ(imported.events, kEvents);
    EXPECT_EQ(imported.clock_records, records());
    EXPECT_EQ(imported.records, 1u);
  }
}

// Without with_meta a CSV is a plain table: header first, no clock records (JSON Lines keeps them).
TEST(ClockRecords, PlainCsvLeavesThemOut) {
  std::ostringstream csv;
  const auto clocks = records();
  write_events_csv(csv, kEvents, EventExportOptions{.clocks = clocks, .origins = {}, .with_meta = false});
  EXPECT_TRUE(csv.str().starts_with("scenario,session,label,node,")) << csv.str();
  EXPECT_EQ(csv.str().find('#'), std::string::npos) << csv.str();
  const auto file = import_text(csv.str(), "x", std::nullopt, {});
  EXPECT_EQ(std::get<EventImport>(file.content).events, kEvents);
  EXPECT_TRUE(std::get<EventImport>(file.content).clock_records.empty());
}

TEST(ClockRecords, ReadersThatSkipThemStillWork) {
  std::ostringstream csv, jsonl;
  const auto clocks = records();
  const EventExportOptions options{.clocks = clocks, .origins = {}, .with_meta = true};
  write_events_csv(csv, kEvents, options);
  write_events_jsonl(jsonl, kEvents, options);
  // A CSV reader that skips '#' lines sees the header and the events only.
  std::istringstream lines(csv.str());
  std::string line;
  std::vector<std::string> data;
  while (std::getline(lines, line))
    if (line.front() != '#') data.push_back(line);
  EXPECT_EQ(data.size(), 2u);
  // A JSONL reader that keeps objects with time_ns sees the events only.
  std::istringstream objects(jsonl.str());
  int with_time = 0;
  while (std::getline(objects, line)) with_time += nlohmann::json::parse(line).contains("time_ns") ? 1 : 0;
  EXPECT_EQ(with_time, 1);
}

TEST(ClockRecords, MalformedRecordsNameTheLineAndMember) {
  expect_data_error(
      [] {
        import_events_csv("# format: m2mlat-events/1\n# clock: {\"node\":\"v\",\"time_ns\":1.5e18,"
                          "\"source\":\"sim\",\"synchronised\":true}\nnode,channel,time_ns\n",
                          "a.csv", {});
      },
      {"a.csv:2:", "time_ns"});
  expect_data_error(
      [] {
        import_events_jsonl("{\"format\":\"m2mlat-events/1\",\"clock_sample\":{\"node\":\"v\",\"time_ns\":1,"
                            "\"source\":\"sim\"}}\n",
                            "b.jsonl", {});
      },
      {"b.jsonl:1:", "synchronised"});
  expect_data_error(
      [] {
        import_events_jsonl("{\"format\":\"m2mlat-events/1\",\"node\":\"v\",\"clock_sample\":{}}\n", "c.jsonl", {});
      },
      {"c.jsonl:1:", "clock_sample"});
}

TEST(ChronyLog, StepsWithTheirSizeTimeAndResolution) {
  const auto log = import_chrony_log(
      "2026-06-01T09:02:00.041159+00:00 vehicle chronyd[754]: Selected source 10.0.0.1\n"
      "2026-06-01T09:02:00.041159+00:00 vehicle chronyd[754]: System clock wrong by 0.040000 seconds\n"
      "2026-06-01T09:02:00.041160+00:00 vehicle chronyd[754]: System clock was stepped by 0.040000 seconds\n"
      "2026-06-01T11:30:00+02:00 vehicle chronyd[754]: System clock was stepped by -0.040001 seconds\n"
      "2026-06-01T09:45:00Z System clock wrong by 0.5 seconds, adjustment started\n"
      "2026-06-01T09:50:00.5Z vehicle chronyd[754]: Backward time jump detected!\n"
      "2026-06-01 10:00:00Z System clock wrong by -0.002320 seconds (step)\n",
      "chrony.log");
  ASSERT_EQ(log.steps.size(), 4u);
  constexpr std::int64_t k0900 = 1'780'304'400'000'000'000;  // 2026-06-01T09:00:00Z
  EXPECT_EQ(log.steps[0], (ChronyStep{3, k0900 + 120'041'160'000, 1000, 40'000'000}));
  EXPECT_EQ(log.steps[1], (ChronyStep{4, k0900 + 1'800'000'000'000, 1'000'000'000, -40'001'000}));
  EXPECT_EQ(log.steps[2], (ChronyStep{6, k0900 + 3'000'500'000'000, 100'000'000, std::nullopt}));
  EXPECT_EQ(log.steps[3], (ChronyStep{7, k0900 + 3'600'000'000'000, 1'000'000'000, -2'320'000}));
  EXPECT_EQ(log.chrony_lines, 6u);
  EXPECT_EQ(log.ignored_lines, 1u);
}

TEST(ChronyLog, InitialOffsetsLeapSecondsAndFailedSteps) {
  const auto log = import_chrony_log(
      "2026-06-01T09:00:00Z chronyd[1]: System's initial offset : 0.250000 seconds fast of true (step)\n"
      "2026-06-01T09:01:00Z chronyd[1]: System's initial offset : 1.500000 seconds slow of true (step)\n"
      "2026-06-01T09:02:00Z chronyd[1]: System's initial offset : 0.000100 seconds fast of true (slew)\n"
      "2026-06-01T09:03:00Z chronyd[1]: System clock wrong by 3.000000 seconds (step)\n"
      "2026-06-01T09:03:00Z chronyd[1]: Could not step system clock\n"
      "2026-06-01T09:04:00Z chronyd[1]: System clock wrong by 2.535004 seconds\n"
      "2026-06-01T09:04:00Z chronyd[1]: Could not step system clock\n"
      "2026-06-30T23:59:60Z chronyd[1]: System clock was stepped for leap second\n",
      "chrony.log");
  constexpr std::int64_t k0900 = 1'780'304'400'000'000'000;  // 2026-06-01T09:00:00Z
  ASSERT_EQ(log.steps.size(), 3u);
  EXPECT_EQ(log.steps[0], (ChronyStep{1, k0900, 1'000'000'000, -250'000'000}));
  EXPECT_EQ(log.steps[1], (ChronyStep{2, k0900 + 60'000'000'000, 1'000'000'000, 1'500'000'000}));
  EXPECT_EQ(log.steps[2].line, 8);
  EXPECT_EQ(log.steps[2].size_ns, std::nullopt);  // its sign is not in the line
  EXPECT_EQ(log.failed_steps, 2u);
  EXPECT_EQ(log.chrony_lines, 8u);
}

TEST(ChronyLog, TheJournalsJsonLines) {
  const auto log = import_chrony_log(
      R"({"__REALTIME_TIMESTAMP":"1780304400123456","_SYSTEMD_UNIT":"chrony.service","MESSAGE":"System clock wrong by 16.044301 seconds"})"
      "\n"
      R"({"__REALTIME_TIMESTAMP":"1780304416200000","_SYSTEMD_UNIT":"chrony.service","MESSAGE":"System clock was stepped by 16.044301 seconds"})"
      "\n"
      R"({"__REALTIME_TIMESTAMP":"1780304417000000","MESSAGE":"Selected source 10.0.0.1"})"
      "\n",
      "journal.json");
  ASSERT_EQ(log.steps.size(), 1u);
  EXPECT_EQ(log.steps[0], (ChronyStep{2, 1'780'304'416'200'000'000, 1000, 16'044'301'000}));
  EXPECT_EQ(log.chrony_lines, 2u);
  EXPECT_EQ(log.ignored_lines, 1u);
  expect_data_error([] { import_chrony_log(R"({"MESSAGE":"System clock was stepped by 1.0 seconds"})", "j.json"); },
                    {"j.json:1:"});
}

// A real chronyd's debug log from another system (../shared/data/real/chrony, beside the checkout):
// eleven "wrong by" notices, none of them a step.
TEST(ChronyLog, ARealDebugLogOfNoticesHasNoSteps) {
  const std::string path = std::string(M2MLAT_TEST_DATA) + "/../../../shared/data/real/chrony/omnios_chronyd_debug.log";
  std::ifstream in(path);
  ASSERT_TRUE(in) << path << " (the shared data beside the checkout) is missing";
  std::stringstream text;
  text << in.rdbuf();
  const auto log = import_chrony_log(text.str(), path);
  EXPECT_TRUE(log.steps.empty());
  EXPECT_EQ(log.chrony_lines, 11u);
  EXPECT_EQ(log.ignored_lines, 0u);
}

TEST(ChronyLog, UnplaceableOrForeignLogsAreRefused) {
  expect_data_error(
      [] { import_chrony_log("Mar 14 14:06:28 pi chronyd[754]: System clock was stepped by 16.044301 seconds\n", "s.log"); },
      {"s.log:1:", "short-iso-precise"});
  expect_data_error(
      [] { import_chrony_log("2026-06-01T09:02:00Z x: System clock was stepped by 0.04x seconds\n", "t.log"); },
      {"t.log:1:", "step"});
  expect_data_error([] { import_chrony_log("hello\nworld\n", "u.log"); }, {"u.log", "chronyd"});
}

}  // namespace m2mlat::formats::clock_records_test
