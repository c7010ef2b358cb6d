// The archive's connection strings (where they come from, how they are shown: never with the
// password), COPY's field escaping, the date filter's parser and the naming of scenarios shared by
// several campaigns. No server needed.
#include "m2mlat/archive/connection.hpp"

#include <gtest/gtest.h>

#include <fstream>

#include "m2mlat/archive/read.hpp"
#include "m2mlat/core/error.hpp"
#include "temp_dir.hpp"

namespace m2mlat::archive {
namespace {

core::ErrorKind kind_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const core::Error& e) {
    return e.kind();
  }
  ADD_FAILURE() << "no core::Error thrown";
  return core::ErrorKind::internal;
}

TEST(ArchiveUrl, TellsConnectionStringsFromFiles) {
  EXPECT_TRUE(is_archive_url("postgresql://lab.example/archive"));
  EXPECT_TRUE(is_archive_url("postgres:///lab?host=/run/postgresql"));
  EXPECT_FALSE(is_archive_url("campaign.db"));
  EXPECT_FALSE(is_archive_url("postgresql.db"));
}

TEST(ArchiveConninfo, DescribeNeverShowsThePassword) {
  EXPECT_EQ(describe("postgresql://alice:s3cret@db.lab:5433/archive"), "alice@db.lab:5433/archive");
  const auto keywords = describe("host=/run/pg port=6000 user=bob password=hunter2 dbname=lab");
  EXPECT_EQ(keywords, "bob@/run/pg:6000/lab");
  EXPECT_EQ(keywords.find("hunter2"), std::string::npos);
  EXPECT_EQ(describe("postgresql:///lab?host=/tmp/x&user=m2mlat&password=pw"), "m2mlat@/tmp/x:5432/lab");
}

TEST(ArchiveConninfo, FromTheArgumentAFileOrTheEnvironment) {
  testing::TempDir dir;
  EXPECT_EQ(resolve_conninfo("postgresql://u@h/db", ""), "postgresql://u@h/db");
  EXPECT_EQ(resolve_conninfo("", ""), "");  // libpq takes PGHOST, PGUSER, PGPASSFILE, ...
  std::ofstream(dir.file("url.txt")) << "postgresql://u:pw@h/db\r\nsecond line ignored\n";
  EXPECT_EQ(resolve_conninfo("", dir.file("url.txt")), "postgresql://u:pw@h/db");
}

TEST(ArchiveConninfo, RefusesWhatItCannotUse) {
  testing::TempDir dir;
  EXPECT_EQ(kind_of([] { resolve_conninfo("postgresql://[bad", ""); }), core::ErrorKind::usage);
  EXPECT_EQ(kind_of([&] { resolve_conninfo("postgresql://h/db", dir.file("u")); }), core::ErrorKind::usage);
  EXPECT_EQ(kind_of([&] { resolve_conninfo("", dir.file("missing.txt")); }), core::ErrorKind::no_input);
  std::ofstream(dir.file("empty.txt")) << "\n";
  EXPECT_EQ(kind_of([&] { resolve_conninfo("", dir.file("empty.txt")); }), core::ErrorKind::usage);
  try {
    resolve_conninfo("postgresql://u:topsecret@[bad", "");
    FAIL() << "accepted";
  } catch (const core::Error& e) {
    EXPECT_EQ(std::string(e.what()).find("topsecret"), std::string::npos) << e.what();
  }
}

TEST(ArchiveConninfo, AnUnreachableServerIsAnIoErrorWithoutThePassword) {
  testing::TempDir dir;
  const auto url = "postgresql://m2mlat:pw-never-shown@/lab?host=" + dir.file("no-server");
  try {
    Connection::open(url);
    FAIL() << "connected";
  } catch (const core::Error& e) {
    EXPECT_EQ(e.kind(), core::ErrorKind::io);
    const std::string what = e.what();
    EXPECT_NE(what.find("cannot connect"), std::string::npos) << what;
    EXPECT_EQ(what.find("pw-never-shown"), std::string::npos) << what;
  }
}

TEST(ArchiveCopy, EscapesCopyTextFormat) {
  EXPECT_EQ(copy_text("plain"), "plain");
  EXPECT_EQ(copy_text("a\tb\nc\\d\re"), "a\\tb\\nc\\\\d\\re");
  EXPECT_EQ(copy_text(""), "");
}

TEST(ArchiveDates, ParsesUtcDays) {
  EXPECT_EQ(parse_date("1970-01-01", "--since"), 0);
  EXPECT_EQ(parse_date("2026-06-01", "--since"), 1780272000LL * 1'000'000'000);
  for (const char* bad : {"2026-02-30", "2026-6-1", "26-06-01", "2026-06-01x", "yesterday", ""}) try {
      parse_date(bad, "--until");
      ADD_FAILURE() << bad << " accepted";
    } catch (const core::Error& e) {
      EXPECT_EQ(e.kind(), core::ErrorKind::usage);
      EXPECT_NE(std::string(e.what()).find("--until"), std::string::npos) << e.what();
    }
}

TEST(ArchiveNames, SharedScenariosGetTheirCampaignsName) {
  CampaignInfo a, b;
  a.id = 1, a.name = "spring", a.scenarios = {{"static_5g", 2, 10}, {"urban", 2, 10}};
  b.id = 2, b.name = "autumn", b.scenarios = {{"static_5g", 2, 10}};
  const auto names = scenario_names({a, b});
  EXPECT_EQ(names.at({1, "static_5g"}), "spring/static_5g");
  EXPECT_EQ(names.at({2, "static_5g"}), "autumn/static_5g");
  EXPECT_EQ(names.at({1, "urban"}), "urban");
  EXPECT_EQ(scenario_names({b}).at({2, "static_5g"}), "static_5g");
}

}  // namespace
}  // namespace m2mlat::archive
