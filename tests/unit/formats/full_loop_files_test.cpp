// The full-loop rig's two files: the result CSV (columns by name, empty = missing, every refusal
// naming file, line and field) and the camera-to-monitor latencies (exact decimal ms), and their
// detection by header.
#include <gtest/gtest.h>

#include "formats_test_support.hpp"
#include "m2mlat/formats/camera_latency.hpp"
#include "m2mlat/formats/format.hpp"
#include "m2mlat/formats/full_loop_csv.hpp"
#include "m2mlat/formats/import_file.hpp"

namespace m2mlat::formats::full_loop_files_test {
namespace {

using test::expect_data_error;
using test::fixture;

constexpr std::string_view kHeader =
    "VEHICLE_GY_ON,VEHICLE_GY_OFF,LED_ON,STATION_GY_ON,STATION_GY_OFF,PHOTOTRANSISTOR\n";

std::string with_header(std::string_view rows) { return std::string(kHeader) + std::string(rows); }

TEST(FullLoopCsv, ReadsEveryFieldExactlyInTheRigsOrder) {
  const auto imported = import_full_loop_csv(
      with_header("9223372036854775807,2,3,-9223372036854775808,5,1762872545152400321\n"), "r.csv");
  ASSERT_EQ(imported.rows.size(), 1u);
  const auto& row = imported.rows[0];
  EXPECT_EQ(row.line, 2);
  EXPECT_EQ(row.ns[kVehicleGyOn], INT64_MAX);
  EXPECT_EQ(row.ns[kVehicleGyOff], 2);
  EXPECT_EQ(row.ns[kLedOn], 3);
  EXPECT_EQ(row.ns[kStationGyOn], INT64_MIN);
  EXPECT_EQ(row.ns[kStationGyOff], 5);
  EXPECT_EQ(row.ns[kPhototransistor], 1762872545152400321);  // beyond a double's 2^53: read as an integer
}

TEST(FullLoopCsv, ColumnsAreFoundByNameWithSpacesCrlfAndBlankLines) {
  const auto text =
      "\xEF\xBB\xBF PHOTOTRANSISTOR ,STATION_GY_ON,VEHICLE_GY_ON,LED_ON,STATION_GY_OFF,VEHICLE_GY_OFF\r\n"
      "\r\n"
      " 60 , 10 , 20 , 30 , 40 , 50 \r\n";
  const auto imported = import_full_loop_csv(text, "r.csv");
  ASSERT_EQ(imported.rows.size(), 1u);
  const auto& row = imported.rows[0];
  EXPECT_EQ(row.line, 3);  // blank lines count, as in an editor
  EXPECT_EQ(row.ns[kPhototransistor], 60);
  EXPECT_EQ(row.ns[kStationGyOn], 10);
  EXPECT_EQ(row.ns[kVehicleGyOn], 20);
  EXPECT_EQ(row.ns[kLedOn], 30);
  EXPECT_EQ(row.ns[kStationGyOff], 40);
  EXPECT_EQ(row.ns[kVehicleGyOff], 50);
}

TEST(FullLoopCsv, AnEmptyFieldIsAMissingValueNotZero) {
  const auto imported = import_full_loop_csv(with_header("1,,3,4,5,\n,,,,,\n"), "r.csv");
  ASSERT_EQ(imported.rows.size(), 2u);
  EXPECT_EQ(imported.rows[0].ns[kVehicleGyOn], 1);
  EXPECT_FALSE(imported.rows[0].ns[kVehicleGyOff].has_value());
  EXPECT_FALSE(imported.rows[0].ns[kPhototransistor].has_value());
  for (const auto& value : imported.rows[1].ns) EXPECT_FALSE(value.has_value());
}

TEST(FullLoopCsv, RefusalsNameFileLineAndField) {
  expect_data_error([] { import_full_loop_csv(with_header("1,2,3,4,5,6\n1,2,x3,4,5,6\n"), "r.csv"); },
                    {"r.csv:3:", "field LED_ON", "'x3'", "not an integer"});
  expect_data_error([] { import_full_loop_csv(with_header("1,2,3,4,5,9223372036854775808\n"), "r.csv"); },
                    {"r.csv:2:", "field PHOTOTRANSISTOR", "out of range"});
  expect_data_error([] { import_full_loop_csv(with_header("1,2,3,4,5,1.5\n"), "r.csv"); },
                    {"r.csv:2:", "field PHOTOTRANSISTOR", "not an integer"});
  expect_data_error([] { import_full_loop_csv(with_header("1,2,\"3,4,5,6\n"), "r.csv"); },
                    {"r.csv:2:", "unterminated quote"});
  expect_data_error([] { import_full_loop_csv(with_header("1,2,\"3\",4,5,6\n"), "r.csv"); },
                    {"r.csv:2:", "field LED_ON", "not an integer"});
  expect_data_error([] { import_full_loop_csv(with_header("1,2,3,4,5\n"), "r.csv"); },
                    {"r.csv:2:", "expected 6 fields", "found 5"});
  expect_data_error([] { import_full_loop_csv(with_header("1,2,3,4,5,6,7\n"), "r.csv"); },
                    {"r.csv:2:", "found 7"});
  expect_data_error(
      [] { import_full_loop_csv(with_header("1,2,3,4,5,6\n") + std::string(kHeader), "r.csv"); },
      {"r.csv:3:", "header appears again"});
}

TEST(FullLoopCsv, AWrongHeaderIsNamed) {
  expect_data_error(
      [] {
        import_full_loop_csv(
            "VEHICLE_GY_ON,VEHICLE_GY_OFF,LED,STATION_GY_ON,STATION_GY_OFF,PHOTOTRANSISTOR\n", "r.csv");
      },
      {"r.csv:1:", "header column 3", "'LED'"});
  expect_data_error(
      [] {
        import_full_loop_csv("VEHICLE_GY_ON,VEHICLE_GY_OFF,LED_ON,STATION_GY_ON,STATION_GY_OFF\n", "r.csv");
      },
      {"r.csv:1:", "lacks the column PHOTOTRANSISTOR"});
  expect_data_error(
      [] {
        import_full_loop_csv("LED_ON,LED_ON,VEHICLE_GY_ON,VEHICLE_GY_OFF,STATION_GY_ON,STATION_GY_OFF\n",
                             "r.csv");
      },
      {"r.csv:1:", "header column 2 repeats LED_ON"});
  expect_data_error([] { import_full_loop_csv("\n \n", "r.csv"); }, {"r.csv:", "is empty"});
}

TEST(FullLoopCsv, ATruncatedLastLineIsRefusedByTheImport) {
  expect_data_error([] { import_text(with_header("1,2,3,4,5,6\n1,2,3,4,5,6"), "r.csv", std::nullopt, {}); },
                    {"r.csv:3:"});
}

TEST(CameraLatency, ParsesDecimalMillisecondsExactly) {
  const auto imported =
      import_camera_latency("LATENCY (ms)\r\n45.123456\r\n 47.2 \r\n\r\n52\r\n-1.5\r\n0.000001\r\n", "c.txt");
  EXPECT_EQ(imported.latency_ns,
            (std::vector<std::int64_t>{45'123'456, 47'200'000, 52'000'000, -1'500'000, 1}));
  EXPECT_EQ(imported.lines, (std::vector<long>{2, 3, 5, 6, 7}));
}

TEST(CameraLatency, RefusesWhatIsNotAWholeNanosecondOrNotANumber) {
  // A 7th decimal is below a nanosecond: refused rather than rounded.
  expect_data_error([] { import_camera_latency("LATENCY (ms)\n12.3456789\n", "c.txt"); },
                    {"c.txt:2:", "field LATENCY (ms)", "'12.3456789'", "at most 6 decimals"});
  expect_data_error([] { import_camera_latency("LATENCY (ms)\n12\nabc\n", "c.txt"); }, {"c.txt:3:", "'abc'"});
  expect_data_error([] { import_camera_latency("LATENCY (us)\n12\n", "c.txt"); },
                    {"c.txt:1:", "header is 'LATENCY (us)'", "expected 'LATENCY (ms)'"});
  expect_data_error([] { import_camera_latency("", "c.txt"); }, {"c.txt:", "is empty"});
}

TEST(FullLoopFiles, DetectedByTheirHeader) {
  EXPECT_EQ(detect_format(with_header("")), Format::full_loop_csv);
  EXPECT_EQ(
      detect_format("PHOTOTRANSISTOR,LED_ON,VEHICLE_GY_ON,STATION_GY_ON,VEHICLE_GY_OFF,STATION_GY_OFF\n"),
      Format::full_loop_csv);
  // A misspelt column still goes to this reader, which names it.
  EXPECT_EQ(detect_format("VEHICLE_GY_ON,VEHICLE_GY_OFF,LED,STATION_GY_ON,STATION_GY_OFF,PHOTO\n"),
            Format::full_loop_csv);
  EXPECT_EQ(detect_format("LATENCY (ms)\n12.5\n"), Format::camera_latency);
  EXPECT_EQ(detect_format(" LATENCY (ms) \r\n12.5\r\n"), Format::camera_latency);
  EXPECT_EQ(detect_format("LATENCY\n12.5\n"), std::nullopt);
  EXPECT_EQ(content_of(Format::full_loop_csv), Content::full_loop);
  EXPECT_EQ(content_of(Format::camera_latency), Content::latencies);
  EXPECT_FALSE(is_importable(Format::full_loop_csv));
  EXPECT_EQ(parse_format("full-loop-csv"), Format::full_loop_csv);
  EXPECT_EQ(parse_format("camera-latency"), Format::camera_latency);
}

TEST(FullLoopFiles, TheFixturesImportByDetection) {
  const auto small = import_file(fixture("full_loop/full_loop_small.csv"), std::nullopt, {});
  const auto reordered = import_file(fixture("full_loop/full_loop_reordered.csv"), std::nullopt, {});
  ASSERT_EQ(small.format, Format::full_loop_csv);
  ASSERT_EQ(reordered.format, Format::full_loop_csv);
  const auto& a = std::get<FullLoopImport>(small.content).rows;
  const auto& b = std::get<FullLoopImport>(reordered.content).rows;
  ASSERT_EQ(a.size(), 10u);
  ASSERT_EQ(b.size(), 10u);
  for (std::size_t i = 0; i < a.size(); ++i) EXPECT_EQ(a[i].ns, b[i].ns) << "row " << i;
  const auto camera = import_file(fixture("full_loop/camera_latency_small.txt"), std::nullopt, {});
  ASSERT_EQ(camera.format, Format::camera_latency);
  EXPECT_EQ(std::get<CameraLatencyImport>(camera.content).latency_ns.size(), 9u);  // and one blank line
  EXPECT_THROW(read_timestamps(fixture("full_loop/full_loop_small.csv"), std::nullopt), core::Error);
}

}  // namespace
}  // namespace m2mlat::formats::full_loop_files_test
