// The request parsers: what they accept exactly, and that every malformed value is a 400.
#include "m2mlat/net/query.hpp"

#include <gtest/gtest.h>

#include <functional>
#include <vector>

namespace m2mlat::net {
namespace {

int status_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const RequestError& e) {
    return e.status();
  }
  return 0;
}

TEST(Query, AfterTakesDigitsUpToInt64Max) {
  EXPECT_EQ(parse_after(std::nullopt), 0);
  EXPECT_EQ(parse_after("0"), 0);
  EXPECT_EQ(parse_after("0042"), 42);
  EXPECT_EQ(parse_after("9223372036854775807"), 9223372036854775807);
  for (const char* bad : {"", "-1", "+1", " 1", "1 ", "1e3", "0x10", "9223372036854775808",
                          "99999999999999999999", "00000000000000000001", "1.0", "abc"})
    EXPECT_EQ(status_of([&] { parse_after(bad); }), 400) << bad;
}

TEST(Query, TheMessageNamesTheParameterAndShowsTheValueEscaped) {
  try {
    parse_after(std::string_view("\x01zz'", 4), "Last-Event-ID");
    FAIL();
  } catch (const RequestError& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find("Last-Event-ID"), std::string::npos);
    EXPECT_NE(message.find("\\x01zz\\x27"), std::string::npos) << message;
  }
}

TEST(Query, LimitIsOneToTheMaximum) {
  EXPECT_EQ(parse_limit(std::nullopt), kDefaultLimit);
  EXPECT_EQ(parse_limit("1"), 1u);
  EXPECT_EQ(parse_limit("10000"), kMaxLimit);
  for (const char* bad : {"0", "10001", "-5", "", "1000000000000000000000", "ten"})
    EXPECT_EQ(status_of([&] { parse_limit(bad); }), 400) << bad;
}

TEST(Query, SessionBodyTakesOnlyLabelAndScenario) {
  EXPECT_EQ(parse_session_request(""), SessionRequest{});
  EXPECT_EQ(parse_session_request(" \n"), SessionRequest{});
  EXPECT_EQ(parse_session_request("{}"), SessionRequest{});
  EXPECT_EQ(parse_session_request(R"({"label":"run-3","scenario":"urban"})"),
            (SessionRequest{"run-3", "urban"}));
  EXPECT_EQ(parse_session_request(R"({"scenario":"ümlaut"})"), (SessionRequest{"", "ümlaut"}));
  for (const std::string& bad :
       std::vector<std::string>{R"({"label":3})", R"({"label":null})", R"({"lable":"x"})", R"([])", R"("x")",
                                "{", "{\"label\":\"a\\u0001\"}", "{\"label\":\"\xff\"}",
                                R"({"label":"x"} trailing)", "{\"label\":\"" + std::string(257, 'a') + "\"}"})
    EXPECT_EQ(status_of([&] { parse_session_request(bad); }), 400) << bad;
  EXPECT_EQ(parse_session_request("{\"label\":\"" + std::string(256, 'a') + "\"}").label.size(), 256u);
}

TEST(Query, BearerTokens) {
  EXPECT_EQ(parse_bearer("Bearer abc-DEF_012.~+/=="), "abc-DEF_012.~+/==");
  EXPECT_EQ(parse_bearer("bearer  tok "), "tok");
  EXPECT_EQ(parse_bearer("BEARER tok"), "tok");
  for (const char* bad : {"", "Bearer", "Bearer ", "Basic dXNlcjpwYXNz", "Bearer a b", "Bearer =abc",
                          "Bearer a=b", "Bearertok", "Bearer tök"})
    EXPECT_FALSE(parse_bearer(bad).has_value()) << bad;
}

}  // namespace
}  // namespace m2mlat::net
