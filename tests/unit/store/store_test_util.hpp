// Helpers for the store tests: a temporary directory removed at the end of the test, small
// factories for sessions and events, and an edit of a store file as another tool could make it.
// (Shared here, not defined per file: the unity build compiles several test files as one.)
#pragma once

#include <gtest/gtest.h>

#include <cstdint>
#include <filesystem>
#include <string>

#include "m2mlat/core/event.hpp"
#include "m2mlat/core/time.hpp"
#include "m2mlat/store/records.hpp"
#include "m2mlat/store/sqlite.hpp"
#include "temp_dir.hpp"

namespace m2mlat::store::test {

using m2mlat::testing::TempDir;

inline core::TimePoint rt(std::int64_t ns) { return core::TimePoint::from_ns(core::Clock::realtime, ns); }

inline Session make_session(const std::string& node, const std::string& label = "run") {
  Session s;
  s.label = label;
  s.scenario = "bench";
  s.node = node;
  s.role = core::Role::effect;
  s.config_json = R"({"window_ms": 2000})";
  s.start = rt(1'700'000'000'000'000'000);
  return s;
}

inline core::Event make_event(const std::string& node, const std::string& channel, std::int64_t ns,
                              std::uint64_t seqno = 0) {
  core::Event e;
  e.node = node;
  e.channel = channel;
  e.edge = core::Edge::falling;
  e.time = rt(ns);
  e.seqno = seqno;
  e.line_seqno = seqno;
  return e;
}

inline bool contains(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

// Edits the file as another tool could, around the store's rules (CHECK clauses switched off).
inline void edit(const std::string& path, const std::string& sql) {
  auto db = sqlite::Database::open(path, sqlite::Database::Mode::read_write);
  db.exec("PRAGMA ignore_check_constraints = ON");
  db.exec(sql);
}

}  // namespace m2mlat::store::test
