// The live stage breakdown (docs/breakdown.md, "Live"): each live pair joined to the markers
// collected so far with analysis's own join (analysis::event_stages) and statistics
// (analysis::summarize_stages), so the live figure is the offline `stats --stages` one.
//
// Markers reach the campaign store in pull order, not time order: a pair's effect may be stored
// before the operator's command markers that explain it. So a pair is joined again at every update
// while it is recent, and its join is kept ("frozen") only once the newest data seen (events or
// markers, ns on CLOCK_REALTIME) lies `retry_window` past its effect. The window bounds what the live
// view holds and redoes: markers older than every pair still open (less one window) are dropped, so
// memory and the cost of an update follow the window, not the campaign's length; a pull lag longer
// than the window (an agent unreachable for longer) leaves the frozen chains as they were, and only
// the final update (LivePairing's finish: every marker of the store, attach_breakdown) gives the
// offline figure then.
#pragma once

#include <cstdint>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "m2mlat/analysis/breakdown.hpp"
#include "m2mlat/analysis/scenario_result.hpp"
#include "m2mlat/analysis/stage_rule.hpp"
#include "m2mlat/core/time.hpp"
#include "m2mlat/markers/marker.hpp"
#include "m2mlat/store/store.hpp"

namespace m2mlat::collect {

class LiveBreakdown {
 public:
  // retry_window: how long past its effect a pair's join is redone (see above), ns.
  LiveBreakdown(analysis::StageRule rule, core::Duration retry_window);

  // Reads the markers the store holds beyond those read before (by row id). Returns how many came.
  std::size_t pull(const store::Store& store);
  // Adds markers that arrived (pull() calls it; tests give markers directly).
  void add(std::vector<markers::Marker> more);

  // Sets result.breakdown over its pairs in_statistics: the frozen joins kept, the others joined
  // again with the markers held. A new scenario drops the frozen joins.
  void update(analysis::ScenarioResult& result);

  const analysis::StageRule& rule() const { return rule_; }
  std::size_t markers_held() const { return markers_.size(); }
  std::size_t frozen() const { return frozen_.size(); }

 private:
  analysis::StageRule rule_;
  core::Duration window_;
  std::vector<markers::Marker> markers_;  // in arrival order
  std::int64_t cursor_ = 0;               // the store's last marker id read
  std::int64_t newest_ns_ = INT64_MIN;    // the newest event or marker time seen
  std::string scenario_;
  // Frozen joins by (cause ns, effect ns): a pair found again keeps its join.
  std::map<std::pair<std::int64_t, std::int64_t>, analysis::EventStages> frozen_;
};

}  // namespace m2mlat::collect
