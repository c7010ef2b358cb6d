// Helpers for the store tests: a temporary directory removed at the end of the test, and small
// factories for sessions and events.
#pragma once

#include <gtest/gtest.h>
#include <stdlib.h>

#include <cstdint>
#include <filesystem>
#include <string>

#include "m2mlat/core/event.hpp"
#include "m2mlat/core/time.hpp"
#include "m2mlat/store/records.hpp"

namespace m2mlat::store::test {

class TempDir {
 public:
  TempDir() {
    std::string pattern = (std::filesystem::temp_directory_path() / "m2mlat-store-XXXXXX").string();
    if (mkdtemp(pattern.data()) == nullptr) throw std::runtime_error("mkdtemp failed");
    path_ = pattern;
  }
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;
  ~TempDir() {
    std::error_code ignored;
    std::filesystem::remove_all(path_, ignored);
  }
  std::string file(const std::string& name) const { return (path_ / name).string(); }

 private:
  std::filesystem::path path_;
};

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

}  // namespace m2mlat::store::test
