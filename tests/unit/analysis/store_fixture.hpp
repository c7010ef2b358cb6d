// What the analysis tests build their stores from: edges at fixed instants, and a session of one
// node with its events, in a store in a fresh temporary folder.
#pragma once

#include <gtest/gtest.h>

#include <cstdint>
#include <string>
#include <vector>

#include "m2mlat/core/event.hpp"
#include "m2mlat/store/store.hpp"
#include "temp_dir.hpp"

namespace m2mlat::analysis::fixture {

inline constexpr std::int64_t kMs = 1'000'000;                  // ns
inline constexpr std::int64_t kS = 1'000 * kMs;                 // ns
inline constexpr std::int64_t kT0 = 1'700'000'000'000'000'000;  // ns since the epoch (2023-11-14)

inline core::TimePoint rt(std::int64_t ns) { return core::TimePoint::from_ns(core::Clock::realtime, ns); }

inline core::Event edge(const std::string& node, const std::string& channel, std::int64_t t_ns,
                        core::Edge e = core::Edge::falling, core::Clock clock = core::Clock::realtime) {
  core::Event ev;
  ev.node = node;
  ev.channel = channel;
  ev.edge = e;
  ev.time = core::TimePoint::from_ns(clock, t_ns);
  return ev;
}

// Begins a session of `node` in `scenario` (started at kT0) and appends `events`; returns its id.
inline std::int64_t add_session(store::Store& s, const std::string& scenario, const std::string& node,
                                core::Role role, const std::vector<core::Event>& events) {
  store::Session info;
  info.scenario = scenario;
  info.node = node;
  info.role = role;
  info.start = rt(kT0);
  const auto id = s.begin_session(info);
  s.append_events(id, events);
  return id;
}

// A store file in a temporary folder of its own, removed with the folder.
class StoreTest : public ::testing::Test {
 private:
  testing::TempDir dir_;  // first: path_ is made from it

 protected:
  std::string file(const std::string& name) const { return dir_.file(name); }
  const std::string path_ = dir_.file("store.db");
};

}  // namespace m2mlat::analysis::fixture
