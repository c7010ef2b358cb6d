// Keys taken from payloads (JSON member, byte range, hash), the sender's stamp in ms, and commands
// matched across two captures into one-way times.
#include <gtest/gtest.h>

#include "m2mlat/core/error.hpp"
#include "m2mlat/markers/capture_writer.hpp"
#include "m2mlat/markers/command_rule.hpp"
#include "m2mlat/markers/markers_file.hpp"
#include "m2mlat/markers/one_way.hpp"

namespace m2mlat::markers {
namespace {

MessageKey key_of(const std::string& rule_text, const std::string& payload, const std::string& sender_ms = "") {
  CommandRule rule;
  rule.key = parse_key_rule(rule_text);
  rule.sender_ms = sender_ms;
  return message_key(rule, bytes_of(payload));
}

TEST(CommandRule, JsonMemberAtTheTopLevelOnly) {
  const std::string payload = R"({"inner":{"id":"wrong"},"list":[{"id":1}],"id":"c-17","stamp":1764000000123})";
  const auto found = key_of("json:id", payload, "stamp");
  ASSERT_TRUE(found.key);
  EXPECT_EQ(*found.key, "c-17");
  EXPECT_EQ(found.sender_ns, 1'764'000'000'123'000'000);
}

TEST(CommandRule, SenderStampInFractionalMsIsExact) {
  const auto found = key_of("json:stamp", R"({"stamp":1764000000123.456789})", "stamp");
  EXPECT_EQ(*found.key, "1764000000123.456789");
  EXPECT_EQ(found.sender_ns, 1'764'000'000'123'456'789);  // exact: no double on the way
  // More than 6 decimals of ms is below 1 ns: not taken as a time (no silent rounding).
  EXPECT_FALSE(key_of("json:s", R"({"s":1764000000123.4567891})", "s").sender_ns.has_value());
}

TEST(CommandRule, PayloadsWithoutTheKey) {
  EXPECT_FALSE(key_of("json:id", R"({"other":1})").key);
  EXPECT_FALSE(key_of("json:id", R"([{"id":1}])").key);
  EXPECT_FALSE(key_of("json:id", "not json").key);
  EXPECT_FALSE(key_of("json:id", R"({"id":{"nested":1}})").key);
  EXPECT_FALSE(key_of("bytes:4:8", "short").key);
}

TEST(CommandRule, ByteRangeAndHash) {
  EXPECT_EQ(*key_of("bytes:1:3", "\x01\xAB\xCD\xEF\x02").key, "abcdef");
  const auto a = key_of("hash", "same payload");
  const auto b = key_of("hash", "same payload");
  const auto c = key_of("hash", "other payload");
  EXPECT_EQ(*a.key, *b.key);
  EXPECT_NE(*a.key, *c.key);
  EXPECT_EQ(*key_of("hash", "").key, "cbf29ce484222325");  // FNV-1a's offset basis
}

TEST(CommandRule, BadRulesNameTheText) {
  for (const char* text : {"json:", "bytes:1", "bytes:x:2", "bytes:0:0", "md5", ""}) {
    try {
      parse_key_rule(text);
      FAIL() << text;
    } catch (const core::Error& e) {
      EXPECT_EQ(e.kind(), core::ErrorKind::usage);
      EXPECT_NE(std::string(e.what()).find(std::string("key '") + text + "'"), std::string::npos) << e.what();
    }
  }
  EXPECT_EQ(to_string(parse_key_rule("bytes:2:8")), "bytes:2:8");
}

Marker at(const std::string& key, std::int64_t ns, std::optional<std::int64_t> sender = std::nullopt) {
  Marker m;
  m.key = key;
  m.time = core::TimePoint::from_ns(core::Clock::realtime, ns);
  if (sender) m.sender_time = core::TimePoint::from_ns(core::Clock::realtime, *sender);
  return m;
}

TEST(OneWay, MatchedByKeyWithExactDifferences) {
  const std::vector<Marker> sent{at("a", 1'000, 900), at("b", 2'000), at("lost", 3'000), at("a", 4'000)};
  const std::vector<Marker> received{at("b", 22'000'005), at("a", 21'000'007), at("stray", 9), at("a", 30'000'000)};
  const auto match = match_one_way(sent, received);
  ASSERT_EQ(match.commands.size(), 2u);
  EXPECT_EQ(match.commands[0].key, "a");
  EXPECT_EQ(match.commands[0].one_way_ns, 21'000'007 - 1'000);
  EXPECT_EQ(match.commands[0].sender_ns, 900);
  EXPECT_EQ(match.commands[1].one_way_ns, 22'000'005 - 2'000);
  EXPECT_EQ(match.sender_only, 1u);
  EXPECT_EQ(match.receiver_only, 1u);  // "stray"
  EXPECT_EQ(match.repeated_keys, 2u);  // the second "a" on each side
  const auto summary = summarize(match);
  EXPECT_EQ(summary.n, 2u);
  EXPECT_DOUBLE_EQ(summary.median_ns, (21'000'007 - 1'000 + 22'000'005 - 2'000) / 2.0);
  const auto csv = one_way_csv(match);
  EXPECT_EQ(csv.rfind("key,sent_ns,", 0), 0u);  // the header first, no comment line
  EXPECT_NE(csv.find("\na,1000,21000007,20999007,20.999007,900,100,20999107,,\n"), std::string::npos) << csv;
}

}  // namespace
}  // namespace m2mlat::markers
