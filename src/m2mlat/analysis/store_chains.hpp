// The full loop's chains (chains.hpp) from recorded data: the input of build_chains read from a store
// that holds both boards (a campaign store, or board stores joined by `m2mlat merge`), or from two
// board stores (the station's and the vehicle's).
//
// Per scenario: the station is the cause side and the vehicle the effect side, chosen as
// selection.hpp chooses them (side_node), among the scenario's sessions that hold a gyroscope trace
// (so that the vehicle's `m2mlat led` session, whatever its role, does not count as a second node);
// --cause/--effect name them, node[/rate channel]. From the station: its rate trace and its photo
// edges (channel `photo_channel`, edge `photo_edge`); from the vehicle: its rate trace and its LED
// writes (channel `led_channel`, rising edges flagged commanded). Every session of each node in the
// scenario contributes (a board recorded the trace and the LED in two sessions), and each board's
// clock samples become its ClockTrack (the per-chain uncertainty's sync term).
//
// The LED write's bound is the largest half-width its session recorded (store::kConfigLedBound in the
// session's configuration), used for every write of that session: conservative. A session without it
// (an older `m2mlat led`, an imported file) takes `default_led_bound`, and a warning says so.
//
// A scenario with gyroscope traces but no LED writes still gives M2M (its chains counted under the gap
// "no_led"); LED writes without a photo channel are refused (the channel name is likely wrong).
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "m2mlat/analysis/chains.hpp"
#include "m2mlat/analysis/full_loop.hpp"
#include "m2mlat/analysis/pipeline.hpp"
#include "m2mlat/core/event.hpp"
#include "m2mlat/core/time.hpp"
#include "m2mlat/store/store.hpp"

namespace m2mlat::analysis {

struct ChainSelection {
  std::optional<core::ChannelRef> station;  // node[/rate channel]; unset: the cause node with a trace
  std::optional<core::ChannelRef> vehicle;  // likewise the effect node
  std::string led_channel = "led";
  std::string photo_channel = "photo";
  std::optional<core::Edge> photo_edge = core::Edge::falling;  // unset: both edges
  core::Duration default_led_bound{100'000};  // a write's half-width when its session has none, ns
  // Live views: only the traces' last window (from the newest stamp of either board's trace less
  // this), and the LED writes and photo edges from its start: a cost per refresh bounded by the
  // window, not the campaign. Unset: everything.
  std::optional<core::Duration> window;
};

struct StoreChainInput {
  ChainInput input;
  std::string station_node, vehicle_node, station_channel, vehicle_channel;  // the traces read
  std::vector<std::string> warnings;            // e.g. the LED bound assumed, no LED writes
  std::optional<std::int64_t> window_start_ns;  // with ChainSelection::window: where the read began
};

// True if any session of `scenario` holds a gyroscope trace.
bool has_rate_traces(const store::Store& store, const std::string& scenario);

// One store with both boards. Throws core::Error(data) naming the store and the scenario: no such
// scenario, no trace on the station or the vehicle node, several rate channels on a node and none
// chosen, LED writes but no photo edges on the station, traces or events on different clocks.
StoreChainInput chain_input(const store::Store& store, const std::string& scenario,
                            const ChainSelection& selection);
// The station's store and the vehicle's store, the same scenario in both.
StoreChainInput chain_input(const store::Store& station, const store::Store& vehicle,
                            const std::string& scenario, const ChainSelection& selection);

// The chains of every scenario of `store` with gyroscope traces (only those in `only` when it is not
// empty), in the order of their first session, as full-loop results named by scenario; the warnings
// are appended to `warnings`, each naming the store and scenario.
std::vector<FullLoopResult> store_chains(const store::Store& store, const std::vector<std::string>& only,
                                         const ChainSelection& selection, const ChainOptions& options,
                                         const stats::SummaryOptions& summary,
                                         std::vector<std::string>& warnings);

// What `stats` and `report` do with stores: every scenario with gyroscope traces is the full loop,
// analysed as chains, not as cause -> effect events. Takes those scenarios away from the pipeline
// (a store whose selected scenarios all have traces leaves `inputs.inputs`; a store with others too
// stays, its traced scenarios listed in `inputs.skip`) and returns their chains, named by scenario,
// stores in the order given. A cause file and an effect file that are both stores are the station's
// and the vehicle's (chain_input of two stores; their traced scenarios, named by the cause's).
// Opens each store read-only, one at a time, before the pipeline opens any.
std::vector<FullLoopResult> take_chain_stores(PipelineInputs& inputs, const ChainSelection& selection,
                                              const ChainOptions& options,
                                              const stats::SummaryOptions& summary,
                                              std::vector<std::string>& warnings);

}  // namespace m2mlat::analysis
