// The chains' input read from stores: the simulated full loop recorded into a store (both boards in
// one, as `m2mlat merge` leaves them, or one store per board) gives the chains of the run itself to
// the ns; what is missing is named.
#include "m2mlat/analysis/store_chains.hpp"

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include "m2mlat/capture/sim_to_store.hpp"
#include "m2mlat/core/error.hpp"
#include "m2mlat/sim/full_loop.hpp"
#include "m2mlat/store/rate_block.hpp"
#include "temp_dir.hpp"

namespace m2mlat::analysis::store_chains_test {

namespace {

sim::FullLoopRun run_of(int manoeuvres, std::uint64_t seed) {
  sim::FullLoopConfig c;
  c.seed = seed;
  c.manoeuvres = manoeuvres;
  return sim::simulate_full_loop(c);
}

ChainResult chains(const ChainInput& in) { return build_chains(in, ChainOptions{}, {}, "loop"); }

// Every chain's links, values, uncertainties and gap, and the counts by gap, equal.
void expect_same_chains(const ChainResult& got, const ChainResult& want) {
  ASSERT_EQ(got.chains.size(), want.chains.size());
  for (std::size_t i = 0; i < want.chains.size(); ++i) {
    const auto &g = got.chains[i], &w = want.chains[i];
    EXPECT_EQ(g.station_onset_ns, w.station_onset_ns) << i;
    EXPECT_EQ(g.vehicle_onset_ns, w.vehicle_onset_ns) << i;
    EXPECT_EQ(g.led_ns, w.led_ns) << i;
    EXPECT_EQ(g.photo_ns, w.photo_ns) << i;
    EXPECT_EQ(g.values, w.values) << i;
    EXPECT_EQ(g.u_ns, w.u_ns) << i;
    EXPECT_EQ(g.gap, w.gap) << i;
  }
  EXPECT_EQ(got.incomplete, want.incomplete);
}

void expect_same_input(const ChainInput& got, const ChainInput& want) {
  ASSERT_EQ(got.station_trace.samples.size(), want.station_trace.samples.size());
  ASSERT_EQ(got.vehicle_trace.samples.size(), want.vehicle_trace.samples.size());
  for (std::size_t k = 0; k < want.vehicle_trace.samples.size(); ++k) {
    EXPECT_EQ(got.vehicle_trace.samples[k].time_ns, want.vehicle_trace.samples[k].time_ns);
    EXPECT_EQ(got.vehicle_trace.samples[k].raw, want.vehicle_trace.samples[k].raw);
  }
  ASSERT_EQ(got.led.size(), want.led.size());
  for (std::size_t k = 0; k < want.led.size(); ++k) {
    EXPECT_EQ(got.led[k].stamp_ns, want.led[k].stamp_ns);
    EXPECT_EQ(got.led[k].bound_ns, want.led[k].bound_ns);
  }
  EXPECT_EQ(got.photo_ns, want.photo_ns);
  EXPECT_EQ(got.station_clock.samples.size(), want.station_clock.samples.size());
  EXPECT_EQ(got.vehicle_clock.samples.size(), want.vehicle_clock.samples.size());
}

// A session of `node` holding only its gyroscope's trace.
void add_trace_session(store::Store& s, const std::string& node, core::Role role,
                       const core::RateTrace& trace) {
  store::Session info;
  info.scenario = "loop";
  info.node = node;
  info.role = role;
  info.start = core::TimePoint::from_ns(trace.clock, trace.samples.front().time_ns);
  const auto id = s.begin_session(info);
  s.append_rate_blocks(
      store::rate_block::split(id, "gyro", trace.clock, trace.counts_per_deg_s, trace.samples));
}

}  // namespace

TEST(StoreChains, OneStoreWithBothBoardsGivesTheRunsChainsToTheNanosecond) {
  testing::TempDir dir;
  const auto run = run_of(12, 7);
  auto store = store::Store::open(dir.file("merged.db"));
  const auto rec = capture::record_full_loop(store, run, capture::FullLoopBoards::both, "sim", "loop");
  EXPECT_NE(rec.led_session, rec.vehicle_session);  // the LED in a session of its own, as `m2mlat led`

  EXPECT_TRUE(has_rate_traces(store, "loop"));
  const auto got = chain_input(store, "loop", {});
  EXPECT_EQ(got.station_node, "station");
  EXPECT_EQ(got.vehicle_node, "vehicle");
  EXPECT_TRUE(got.warnings.empty());
  const auto want = chain_input(run);
  expect_same_input(got.input, want);
  const auto got_chains = chains(got.input), want_chains = chains(want);
  expect_same_chains(got_chains, want_chains);
  // Not vacuous: every manoeuvre is a complete chain with all three quantities.
  ASSERT_TRUE(got_chains.loop.find(LoopQuantity::e2e));
  EXPECT_EQ(got_chains.loop.find(LoopQuantity::e2e)->ns.size(), 12u);
}

TEST(StoreChains, TwoBoardStoresGiveTheSameChains) {
  testing::TempDir dir;
  const auto run = run_of(8, 3);
  auto station = store::Store::open(dir.file("station.db"));
  auto vehicle = store::Store::open(dir.file("vehicle.db"));
  capture::record_full_loop(station, run, capture::FullLoopBoards::station, "sim", "loop");
  capture::record_full_loop(vehicle, run, capture::FullLoopBoards::vehicle, "sim", "loop");
  const auto got = chain_input(station, vehicle, "loop", {});
  expect_same_chains(chains(got.input), chains(chain_input(run)));
  // One board's store alone lacks the other side, and says which.
  try {
    static_cast<void>(chain_input(station, "loop", {}));
    FAIL() << "no vehicle trace accepted";
  } catch (const core::Error& e) {
    EXPECT_EQ(e.kind(), core::ErrorKind::data);
    EXPECT_NE(std::string(e.what()).find("station.db: scenario 'loop' has no vehicle"), std::string::npos)
        << e.what();
  }
}

TEST(StoreChains, TracesWithoutLedGiveM2mAndCountTheMissingLed) {
  testing::TempDir dir;
  const auto run = run_of(6, 11);
  auto store = store::Store::open(dir.file("gyro.db"));
  add_trace_session(store, "station", core::Role::cause, run.station_trace);
  add_trace_session(store, "vehicle", core::Role::effect, run.vehicle_trace);
  const auto got = chain_input(store, "loop", {});
  ASSERT_EQ(got.warnings.size(), 1u);
  EXPECT_NE(got.warnings[0].find("no LED writes on vehicle/led: M2M only"), std::string::npos);
  const auto r = chains(got.input);
  ASSERT_TRUE(r.loop.find(LoopQuantity::m2m));
  EXPECT_EQ(r.loop.find(LoopQuantity::m2m)->ns.size(), 6u);
  EXPECT_TRUE(r.loop.find(LoopQuantity::e2e)->ns.empty());
  EXPECT_EQ(r.incomplete[static_cast<std::size_t>(ChainGap::no_led)], 6u);
  // The M2M values are the run's own.
  const auto want = chains(chain_input(run));
  EXPECT_EQ(r.loop.find(LoopQuantity::m2m)->ns, want.loop.find(LoopQuantity::m2m)->ns);
}

TEST(StoreChains, AWrongPhotoChannelOrRateChannelIsNamed) {
  testing::TempDir dir;
  const auto run = run_of(4, 5);
  auto store = store::Store::open(dir.file("merged.db"));
  capture::record_full_loop(store, run, capture::FullLoopBoards::both, "sim", "loop");
  ChainSelection light;
  light.photo_channel = "light";
  try {
    static_cast<void>(chain_input(store, "loop", light));
    FAIL() << "a missing photo channel accepted";
  } catch (const core::Error& e) {
    const std::string what = e.what();
    EXPECT_NE(
        what.find("4 LED writes on vehicle/led but no photo edges on station/light (its channels: photo)"),
        std::string::npos)
        << what;
  }
  ChainSelection wheel;
  wheel.vehicle = core::ChannelRef{"vehicle", "wheel"};
  EXPECT_THROW(static_cast<void>(chain_input(store, "loop", wheel)), core::Error);
  EXPECT_THROW(static_cast<void>(chain_input(store, "other", {})), core::Error);
}

TEST(StoreChains, AnLedSessionWithoutItsBoundTakesTheStatedDefaultWithAWarning) {
  testing::TempDir dir;
  const auto run = run_of(3, 9);
  auto store = store::Store::open(dir.file("merged.db"));
  add_trace_session(store, "station", core::Role::cause, run.station_trace);
  add_trace_session(store, "vehicle", core::Role::effect, run.vehicle_trace);
  store::Session led;
  led.scenario = "loop";
  led.node = "vehicle";
  led.role = core::Role::cause;  // `m2mlat led`'s default role: the trace decides who is the vehicle
  led.start = core::TimePoint::from_ns(core::Clock::simulated, 0);
  const auto id = store.begin_session(led);
  std::vector<core::Event> writes, photos;
  for (const auto& m : run.manoeuvres) {
    core::Event e;
    e.node = "vehicle";
    e.channel = "led";
    e.edge = core::Edge::rising;
    e.time = core::TimePoint::from_ns(core::Clock::simulated, m.led_stamp_ns);
    e.flags = core::kFlagCommanded;
    writes.push_back(e);
    e.edge = core::Edge::falling;  // the LED's off switch: not a write that lights it
    e.time = core::TimePoint::from_ns(core::Clock::simulated, m.led_stamp_ns + 100'000'000);
    writes.push_back(e);
  }
  store.append_events(id, writes);
  const auto station = store.sessions().front().id;
  for (const auto& m : run.manoeuvres) {
    core::Event p;
    p.node = "station";
    p.channel = "photo";
    p.time = core::TimePoint::from_ns(core::Clock::simulated, m.photo_stamp_ns);
    photos.push_back(p);
  }
  store.append_events(station, photos);

  ChainSelection sel;
  sel.default_led_bound = core::Duration{70'000};
  const auto got = chain_input(store, "loop", sel);
  ASSERT_EQ(got.warnings.size(), 1u);
  EXPECT_NE(got.warnings[0].find("recorded no LED write bound (led_bound_ns): 70.000 us assumed"),
            std::string::npos)
      << got.warnings[0];
  ASSERT_EQ(got.input.led.size(), 3u);
  for (const auto& w : got.input.led) EXPECT_EQ(w.bound_ns, 70'000);
  EXPECT_EQ(chains(got.input).loop.find(LoopQuantity::g2g)->ns.size(), 3u);

  // With the bound in the session's configuration (as `m2mlat led` ends it), no warning and that bound.
  auto config = nlohmann::json::parse(store.session(id)->config_json);
  config[store::kConfigLedBound] = 2'500;
  store.end_session(id, core::TimePoint::from_ns(core::Clock::simulated, run.end_ns), config.dump());
  const auto bounded = chain_input(store, "loop", sel);
  EXPECT_TRUE(bounded.warnings.empty());
  for (const auto& w : bounded.input.led) EXPECT_EQ(w.bound_ns, 2'500);
}

}  // namespace m2mlat::analysis::store_chains_test
