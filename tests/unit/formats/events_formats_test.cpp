// m2mlat's own events CSV and JSON Lines: fixtures, exact round trips (a 1 ns difference must
// survive), versioning, and malformed input; and the pairs exports.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>
#include <sstream>

#include "formats_test_support.hpp"
#include "m2mlat/formats/events_csv.hpp"
#include "m2mlat/formats/events_jsonl.hpp"
#include "m2mlat/formats/import_file.hpp"
#include "m2mlat/formats/pairs_export.hpp"
#include "m2mlat/pairing/pair.hpp"

namespace m2mlat::formats {
namespace {

using test::expect_data_error;
using test::fixture;

core::Event make(std::string node, std::string channel, core::Clock clock, std::int64_t ns,
                 std::uint64_t seqno = 0, std::uint64_t line_seqno = 0, std::uint32_t flags = 0,
                 core::Edge edge = core::Edge::falling) {
  return core::Event{std::move(node), std::move(channel), edge, core::TimePoint::from_ns(clock, ns),
                     seqno,           line_seqno,         flags};
}

// Events that exercise every field: two timestamps 1 ns apart beyond double precision, extreme
// values, names that need CSV quoting or JSON escaping.
std::vector<core::Event> tricky_events() {
  return {
      make("operator", "wheel", core::Clock::realtime, 1'762'872'545'550'296'135, 1, 1),
      make("operator", "wheel", core::Clock::realtime, 1'762'872'545'550'296'136, 2, 2),
      make("vehicle", "wheel", core::Clock::realtime, 1'762'872'546'417'585'462, 18'446'744'073'709'551'615u,
           7, core::kFlagImported | core::kFlagAfterClockStep, core::Edge::rising),
      make("bench, left", "say \"hi\"", core::Clock::monotonic, -1),
      make("#3", "wheel", core::Clock::realtime, 0),
      make(" spaced ", "tab\there", core::Clock::boottime, std::numeric_limits<std::int64_t>::max()),
      make("sim", "ünïcode/ch", core::Clock::simulated, std::numeric_limits<std::int64_t>::min(), 0, 0,
           0xffffffffu)};
}

TEST(EventsCsv, FixtureWithQuotesAndComments) {
  const auto file = import_file(fixture("events_small.csv"), std::nullopt, ImportOptions{});
  EXPECT_EQ(file.format, Format::events_csv);
  const auto& imported = std::get<EventImport>(file.content);
  ASSERT_EQ(imported.events.size(), 3u);
  EXPECT_EQ(imported.events[0],
            make("operator", "wheel", core::Clock::realtime, 1'700'000'100'100'000'000, 1, 1));
  EXPECT_EQ(imported.events[1],
            make("vehicle", "wheel", core::Clock::realtime, 1'700'000'100'950'123'456, 7, 3));
  EXPECT_EQ(imported.events[2],
            make("bench, left", "say \"hi\"", core::Clock::monotonic, -5, 0, 0, 6, core::Edge::rising));
}

TEST(EventsCsv, TimeInDecimalSecondsAndDefaults) {
  ImportOptions options;
  options.edge = core::Edge::rising;
  const auto file = import_file(fixture("events_time_s.csv"), std::nullopt, options);
  EXPECT_EQ(file.format, Format::events_csv);
  const auto& events = std::get<EventImport>(file.content).events;
  ASSERT_EQ(events.size(), 2u);
  EXPECT_EQ(events[0], make("operator", "wheel", core::Clock::realtime, 1'700'000'100'100'000'001, 0, 0, 0,
                            core::Edge::rising));
  EXPECT_EQ(events[1].time.ns(), 1'700'000'100'950'000'000);
}

TEST(EventsCsv, ExactRoundTrip) {
  const std::vector<core::Event> events = tricky_events();
  std::ostringstream out;
  write_events_csv(out, events);
  EXPECT_TRUE(out.str().starts_with(
      "scenario,session,label,node,channel,edge,clock,time_ns,seqno,line_seqno,flag_bits\n"
      ",,,operator,wheel,falling,realtime,1762872545550296135,1,1,0\n"
      ",,,operator,wheel,falling,realtime,1762872545550296136,2,2,0\n"));
  const EventImport back = import_events_csv(out.str(), "round.csv", ImportOptions{});
  EXPECT_EQ(back.events, events);
  EXPECT_EQ(back.events[1].time - back.events[0].time, core::Duration{1});
  // And again: export of the import is byte-identical.
  std::ostringstream again;
  write_events_csv(again, back.events);
  EXPECT_EQ(again.str(), out.str());
}

// Version 1 files (the "# format:" line first, "flags") read as before; a version 2 file gives the
// same events whatever its scenario, session and label say (the import names its own session).
TEST(EventsCsv, ReadsVersionOneAndOrigins) {
  const auto v1 = import_events_csv(
      "# format: m2mlat-events/1\nnode,channel,edge,clock,time_ns,seqno,line_seqno,flags\n"
      "a,w,falling,realtime,5,1,1,4\n",
      "v1.csv", ImportOptions{});
  const auto v2 = import_events_csv(
      "scenario,session,label,node,channel,edge,clock,time_ns,seqno,line_seqno,flag_bits\n"
      "\"urban, 30\",7,run-1,a,w,falling,realtime,5,1,1,4\n",
      "v2.csv", ImportOptions{});
  ASSERT_EQ(v1.events.size(), 1u);
  EXPECT_EQ(v1.events, v2.events);
  EXPECT_EQ(v1.events[0].flags, 4u);
}

// Each run of events names its session; a name with a comma is quoted.
TEST(EventsCsv, OriginsOnEveryRow) {
  const std::vector<core::Event> events = tricky_events();
  const std::vector<EventOrigin> origins{{"urban, 30", 3, "run-1", 1}, {"rural", 4, "", events.size() - 1}};
  std::ostringstream out;
  write_events_csv(out, events, EventExportOptions{.clocks = {}, .origins = origins, .with_meta = false});
  EXPECT_NE(out.str().find("\n\"urban, 30\",3,run-1,operator,"), std::string::npos) << out.str();
  EXPECT_NE(out.str().find("\nrural,4,,operator,"), std::string::npos) << out.str();
  const std::vector<EventOrigin> short_by_one{{"rural", 4, "", events.size() - 1}};
  EXPECT_THROW(write_events_csv(out, events, EventExportOptions{.clocks = {}, .origins = short_by_one}),
               core::Error);
}

TEST(EventsCsv, EmptyExportReadsBackEmpty) {
  std::ostringstream out;
  write_events_csv(out, {});
  EXPECT_TRUE(import_events_csv(out.str(), "none.csv", ImportOptions{}).events.empty());
}

TEST(EventsCsv, MalformedInput) {
  const std::string header = "node,channel,edge,clock,time_ns,seqno,line_seqno,flags\n";
  const std::string good = "a,b,falling,realtime,5,0,0,0\n";
  auto import = [](const std::string& text) { import_events_csv(text, "ev.csv", ImportOptions{}); };
  expect_data_error([&] { import(header + good + "a,b,falling,realtime,5.5,0,0,0\n"); },
                    {"ev.csv:3: field time_ns: '5.5' is not an integer"});
  expect_data_error([&] { import(header + "a,b,up,realtime,5,0,0,0\n"); },
                    {"ev.csv:2: field edge: 'up' is not rising or falling"});
  expect_data_error([&] { import(header + "a,b,falling,utc,5,0,0,0\n"); }, {"ev.csv:2: field clock: 'utc'"});
  expect_data_error([&] { import(header + "a,b,falling,realtime,5,-1,0,0\n"); },
                    {"ev.csv:2: field seqno: '-1' is not a non-negative integer"});
  expect_data_error([&] { import(header + "a,b,falling,realtime,5,0,0,4294967296\n"); },
                    {"ev.csv:2: field flag_bits", "32 bits"});
  expect_data_error([&] { import(header + ",b,falling,realtime,5,0,0,0\n"); },
                    {"ev.csv:2: field node: '' is empty"});
  expect_data_error([&] { import(header + "a,b,falling,realtime,5,0,0\n"); },
                    {"ev.csv:2: expected 8 fields, found 7"});
  expect_data_error([&] { import(header + "\"a,b,falling,realtime,5,0,0,0\n"); },
                    {"ev.csv:2: unterminated quote"});
  expect_data_error([&] { import(header + good + header + good); },
                    {"ev.csv:3: the header appears again (were two files joined?)"});
  expect_data_error([&] { import(header + good + "# format: m2mlat-events/1\n" + header + good); },
                    {"ev.csv:3: a '#' line after the header"});
  expect_data_error([&] { import("# format: m2mlat-events/3\n" + header); },
                    {"ev.csv:1: format 'm2mlat-events/3' is not supported"});
  expect_data_error([&] { import("scenario,session,label,node,channel,time_ns\ns,x,l,a,b,5\n"); },
                    {"ev.csv:2: field session: 'x' is not an integer"});
  expect_data_error([&] { import("node,channel,time_ns,time_ns\n"); },
                    {"ev.csv:1: header column 'time_ns' appears twice (columns 3 and 4)"});
  expect_data_error([&] { import("node,channel,time_ns,colour\n"); },
                    {"ev.csv:1: header column 4 'colour' is not a field of m2mlat-events/2"});
  expect_data_error([&] { import("node,channel,edge\n"); }, {"ev.csv:1: the header needs a time column"});
  expect_data_error([&] { import("node,channel,time_ns,time_s\n"); }, {"ev.csv:1: the header has both"});
  expect_data_error([&] { import("time_ns\n5\n"); },
                    {"ev.csv:1: the header needs the columns node and channel"});
  expect_data_error([&] { import(good); }, {"ev.csv:1: missing header"});
  expect_data_error([&] { import(""); }, {"ev.csv: is empty"});
  expect_data_error([&] { import("node,channel,time_s\na,b,1.0000000001\n"); },
                    {"ev.csv:2: field time_s", "at most 9 decimals"});
  // Accepted: CRLF, BOM, blank lines at the end.
  const EventImport ok = import_events_csv(
      "\xEF\xBB\xBF"
      "node,channel,time_ns\r\na,b,7\r\n\r\n\n",
      "ok.csv", {});
  ASSERT_EQ(ok.events.size(), 1u);
  EXPECT_EQ(ok.events[0].time.ns(), 7);
}

TEST(EventsCsv, ExportRefusesNamesThatCannotReadBack) {
  std::ostringstream out;
  const std::vector<core::Event> bad{make("a\nb", "wheel", core::Clock::realtime, 1)};
  EXPECT_THROW(write_events_csv(out, bad), core::Error);
  const std::vector<core::Event> empty{make("", "wheel", core::Clock::realtime, 1)};
  EXPECT_THROW(write_events_jsonl(out, empty), core::Error);
}

TEST(EventsJsonl, Fixture) {
  const auto file = import_file(fixture("events_small.jsonl"), std::nullopt, ImportOptions{});
  EXPECT_EQ(file.format, Format::events_jsonl);
  const auto& events = std::get<EventImport>(file.content).events;
  ASSERT_EQ(events.size(), 3u);
  EXPECT_EQ(events[0], make("operator", "wheel", core::Clock::realtime, 1'700'000'100'100'000'000, 1, 1));
  EXPECT_EQ(events[1], make("vehicle", "wheel", core::Clock::realtime, 1'700'000'100'950'123'456));
  EXPECT_EQ(events[2], make("vehicle", "wheel", core::Clock::realtime, 1'700'000'101'000'000'001,
                            18'446'744'073'709'551'615u));
}

TEST(EventsJsonl, ExactRoundTrip) {
  const std::vector<core::Event> events = tricky_events();
  std::ostringstream out;
  write_events_jsonl(out, events);
  EXPECT_TRUE(out.str().starts_with(
      "{\"format\":\"m2mlat-events/2\",\"scenario\":null,\"session\":null,\"label\":null,\"node\":\"operator\","
      "\"channel\":\"wheel\",\"edge\":\"falling\",\"clock\":\"realtime\",\"time_ns\":1762872545550296135,"
      "\"seqno\":1,\"line_seqno\":1,\"flag_bits\":0}\n"));
  const EventImport back = import_events_jsonl(out.str(), "round.jsonl", ImportOptions{});
  EXPECT_EQ(back.events, events);
  EXPECT_EQ(back.events[1].time - back.events[0].time, core::Duration{1});
  // Every line is valid JSON for other programs too.
  std::istringstream lines(out.str());
  std::string line;
  while (std::getline(lines, line)) EXPECT_TRUE(nlohmann::json::accept(line)) << line;
  // Zero events: an empty file, which reads back as zero events.
  std::ostringstream none;
  write_events_jsonl(none, {});
  EXPECT_TRUE(import_events_jsonl(none.str(), "none.jsonl", {}).events.empty());
}

TEST(EventsJsonl, MalformedInput) {
  const std::string head = R"({"format":"m2mlat-events/1","node":"a","channel":"b",)";
  const std::string good = head + R"("time_ns":5})" + "\n";
  auto import = [](const std::string& text) { import_events_jsonl(text, "ev.jsonl", ImportOptions{}); };
  expect_data_error([&] { import(good + head + R"("time_ns":1.7628725455502961e18})" + "\n"); },
                    {"ev.jsonl:2: field time_ns:", "is not an integer"});
  expect_data_error([&] { import(head + R"("time_ns":"5"})"); }, {"ev.jsonl:1: field time_ns: '\"5\"'"});
  expect_data_error([&] { import(head + R"("time_s":1.5})"); },
                    {"ev.jsonl:1: field time_s: '1.5' is not a string"});
  expect_data_error([&] { import(head + R"("time_ns":9223372036854775808})"); },
                    {"ev.jsonl:1: field time_ns", "out of range"});
  expect_data_error([&] { import(head + R"("time_ns":5,"time_s":"5"})"); }, {"ev.jsonl:1: field time_s"});
  expect_data_error([&] { import(head + R"("seqno":-1,"time_ns":5})"); },
                    {"ev.jsonl:1: field seqno: '-1' is not a non-negative integer"});
  expect_data_error([&] { import(head + R"("colour":"red","time_ns":5})"); },
                    {"ev.jsonl:1: unknown member 'colour'"});
  expect_data_error([&] { import(R"({"format":"m2mlat-events/1","node":"a","time_ns":5})"); },
                    {"ev.jsonl:1: missing member \"channel\""});
  expect_data_error([&] { import(head + R"("edge":"up","time_ns":5})"); }, {"ev.jsonl:1: field edge"});
  expect_data_error([&] { import(R"({"node":"a","channel":"b","time_ns":5})"); },
                    {"ev.jsonl:1: missing member \"format\""});
  expect_data_error([&] { import(R"({"format":"m2mlat-events/9","node":"a","channel":"b","time_ns":5})"); },
                    {"ev.jsonl:1: field format", "not supported"});
  expect_data_error([&] { import(good + "{\"format\":\n"); }, {"ev.jsonl:2: not valid JSON"});
  // A number beyond a double's range is the JSON library's out_of_range, not its parse_error.
  expect_data_error([&] { import(good + head + R"("time_ns":1e999})" + "\n"); },
                    {"ev.jsonl:2: not valid JSON", "number overflow"});
  expect_data_error([&] { import(good + "[1,2]\n"); }, {"ev.jsonl:2: not a JSON object"});
  // CRLF and blank lines are fine.
  EXPECT_EQ(
      import_events_jsonl(good + "\r\n" + head + R"("time_ns":6})" + "\r\n\n", "ok.jsonl", {}).events.size(),
      2u);
}

TEST(PairsExport, CsvAndJsonlWithOptionalColumns) {
  const auto at = [](std::int64_t ns) { return core::TimePoint::from_ns(core::Clock::realtime, ns); };
  std::vector<PairRow> pairs(2);
  pairs[0].cause_time = at(1'762'872'545'550'296'135);
  pairs[0].effect_time = at(1'762'872'546'417'585'462);
  pairs[1].cause_index = pairs[1].effect_index = 1;
  pairs[1].cause_time = at(1'762'872'549'652'099'111);
  pairs[1].effect_time = at(1'762'872'549'652'099'110);
  pairs[1].flags = pairing::kPairAmbiguous;

  PairExportOptions plain_options;
  plain_options.flags = false;
  std::ostringstream plain;
  write_pairs_csv(plain, pairs, plain_options);
  EXPECT_EQ(
      plain.str(),
      "scenario,session,label,cause_node,cause_channel,effect_node,effect_channel,clock,cause_time_ns,"
      "effect_time_ns,latency_ns,latency_ms\n"
      ",,,operator,wheel,vehicle,wheel,realtime,1762872545550296135,1762872546417585462,867289327,867.289327\n"
      ",,,operator,wheel,vehicle,wheel,realtime,1762872549652099111,1762872549652099110,-1,-0.000001\n");

  const std::vector<std::optional<std::int64_t>> bound{250'000, std::nullopt}, u{40'000, std::nullopt},
      expanded{80'000, std::nullopt};
  PairExportOptions options;
  options.cause = {"remote", "pedal, left"};
  options.max_error_ns = bound;
  options.u_ns = u;
  options.U95_ns = expanded;
  std::ostringstream full;
  write_pairs_csv(full, pairs, options);
  EXPECT_NE(full.str().find("latency_ms,max_error_ns,u_ns,U95_ns,pair_flags\n"), std::string::npos);
  EXPECT_NE(
      full.str().find("remote,\"pedal, left\",vehicle,wheel,realtime,1762872545550296135,1762872546417585462,"
                      "867289327,867.289327,250000,40000,80000,0\n"),
      std::string::npos);
  EXPECT_NE(full.str().find(",-1,-0.000001,,,,1\n"), std::string::npos);
  // Only the columns given are written.
  PairExportOptions bound_only;
  bound_only.max_error_ns = bound;
  std::ostringstream partial;
  write_pairs_csv(partial, pairs, bound_only);
  EXPECT_NE(partial.str().find("latency_ms,max_error_ns,pair_flags\n"), std::string::npos);

  std::ostringstream jsonl;
  write_pairs_jsonl(jsonl, pairs, options);
  std::istringstream lines(jsonl.str());
  std::string line;
  std::vector<nlohmann::json> objects;
  while (std::getline(lines, line)) objects.push_back(nlohmann::json::parse(line));
  ASSERT_EQ(objects.size(), 2u);
  EXPECT_EQ(objects[0]["format"], "m2mlat-pairs/4");
  EXPECT_EQ(objects[0]["cause_channel"], "pedal, left");
  EXPECT_EQ(objects[0]["cause_time_ns"].get<std::int64_t>(), 1'762'872'545'550'296'135);
  EXPECT_EQ(objects[0]["latency_ns"].get<std::int64_t>(), 867'289'327);
  EXPECT_EQ(objects[0]["max_error_ns"].get<std::int64_t>(), 250'000);
  EXPECT_EQ(objects[0]["u_ns"].get<std::int64_t>(), 40'000);
  EXPECT_EQ(objects[0]["U95_ns"].get<std::int64_t>(), 80'000);
  EXPECT_EQ(objects[0]["pair_flags"].get<std::uint32_t>(), 0u);
  EXPECT_TRUE(objects[1]["max_error_ns"].is_null());
  EXPECT_TRUE(objects[1]["u_ns"].is_null());
  EXPECT_EQ(objects[1]["pair_flags"].get<std::uint32_t>(), 1u);
  EXPECT_NE(jsonl.str().find("\"latency_ms\":867.289327,"), std::string::npos);  // exact decimal text

  // Two scenarios, each with its own boards, and the sessions' labels.
  const std::vector<PairGroup> groups{{"a", {"op", "w"}, {"veh", "w"}, 1}, {"b", {"st", "w"}, {"car", "w"}, 1}};
  const std::vector<std::int64_t> sessions{2, 0};
  PairExportOptions grouped;
  grouped.groups = groups;
  grouped.sessions = sessions;
  grouped.labels = {{2, "run 2"}};
  std::ostringstream two;
  write_pairs_csv(two, pairs, grouped);
  EXPECT_NE(two.str().find("\na,2,run 2,op,w,veh,w,realtime,"), std::string::npos) << two.str();
  EXPECT_NE(two.str().find("\nb,,,st,w,car,w,realtime,"), std::string::npos) << two.str();
  const std::vector<PairGroup> too_few{{"a", {"op", "w"}, {"veh", "w"}, 1}};
  grouped.groups = too_few;
  EXPECT_THROW(write_pairs_csv(two, pairs, grouped), core::Error);

  const std::vector<std::optional<std::int64_t>> too_short{1};
  options.u_ns = too_short;
  EXPECT_THROW(write_pairs_csv(plain, pairs, options), core::Error);
}

}  // namespace
}  // namespace m2mlat::formats
