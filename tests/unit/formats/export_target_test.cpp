// Exports through the output-file writer: a refused event or a refused target leaves what was there.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "m2mlat/core/error.hpp"
#include "m2mlat/formats/import_file.hpp"
#include "temp_dir.hpp"

namespace m2mlat::formats {
namespace {

namespace fs = std::filesystem;

std::string read(const fs::path& p) {
  std::ifstream in(p);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

std::vector<core::Event> events_named(const std::string& last_node) {
  std::vector<core::Event> events;
  for (std::int64_t i = 0; i < 20000; ++i)  // past the writer's buffer: part of it reaches the disk
    events.push_back(
        core::Event{i + 1 < 20000 ? "operator" : last_node, "wheel", core::Edge::falling,
                    core::TimePoint::from_ns(core::Clock::realtime, 1'700'000'000'000'000'000 + i),
                    static_cast<std::uint64_t>(i + 1), static_cast<std::uint64_t>(i + 1), 0});
  return events;
}

class ExportTarget : public ::testing::Test {
 protected:
  std::size_t entries() const {
    std::size_t n = 0;
    for ([[maybe_unused]] const auto& e : fs::directory_iterator(dir_)) ++n;
    return n;
  }
  m2mlat::testing::TempDir temp_;
  const fs::path dir_ = temp_.path();
};

// The last event's node name holds a line break: the export is refused (data) after most of it was
// written, and the previous export stays as it was, with no temporary beside it.
TEST_F(ExportTarget, RefusedEventKeepsThePreviousExport) {
  const auto path = (dir_ / "events.csv").string();
  export_events(path, Format::events_csv, events_named("vehicle"));
  const std::string before = read(path);
  try {
    export_events(path, Format::events_csv, events_named("bad\nname"));
    FAIL() << "exported a node name with a line break";
  } catch (const core::Error& e) {
    EXPECT_EQ(e.kind(), core::ErrorKind::data) << e.what();
  }
  EXPECT_EQ(read(path), before);
  EXPECT_EQ(entries(), 1u);
}

TEST_F(ExportTarget, SymlinkRefusedForEventsAndPairs) {
  std::ofstream(dir_ / "victim") << "precious\n";
  fs::create_symlink(dir_ / "victim", dir_ / "out");
  const auto out = (dir_ / "out").string();
  EXPECT_THROW(export_events(out, Format::events_jsonl, events_named("vehicle")), core::Error);
  const std::vector<PairRow> pairs{{0, 0, core::TimePoint::from_ns(core::Clock::realtime, 1),
                                          core::TimePoint::from_ns(core::Clock::realtime, 2)}};
  EXPECT_THROW(export_pairs(out, Format::pairs_csv, pairs), core::Error);
  EXPECT_EQ(read(dir_ / "victim"), "precious\n");
  EXPECT_TRUE(fs::is_symlink(dir_ / "out"));
  EXPECT_EQ(entries(), 2u);
}

}  // namespace
}  // namespace m2mlat::formats
