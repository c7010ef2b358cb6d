// Looking up the session of each pair's cause event in the store.
#include "m2mlat/analysis/pair_sessions.hpp"

#include <algorithm>
#include <limits>
#include <utility>

#include "m2mlat/store/store.hpp"

namespace m2mlat::analysis {

PairSessions store_pair_sessions(const std::string& store_path, std::span<const ScenarioResult> results) {
  PairSessions out;
  out.sessions.resize(results.size());
  store::Options read;
  read.read_only = true;
  const auto store = store::Store::open(store_path, read);
  const auto sessions = store.sessions();
  for (const auto& s : sessions) out.labels[s.id] = s.label;
  for (std::size_t r = 0; r < results.size(); ++r) {
    const ScenarioResult& result = results[r];
    if (result.input.id_kind != "seq") continue;
    // (seq, session) of every event of the cause node's sessions in this scenario, sorted by seq.
    std::vector<std::pair<std::int64_t, std::int64_t>> owner;
    for (const auto& s : sessions) {
      if (s.scenario != result.input.scenario || s.node != result.input.cause_ref.node) continue;
      store::EventFilter filter;
      filter.session_id = s.id;
      const auto stamps = store.timestamps(
          core::TimePoint::from_ns(result.input.clock, std::numeric_limits<std::int64_t>::min()),
          core::TimePoint::from_ns(result.input.clock, std::numeric_limits<std::int64_t>::max()), filter);
      for (const std::int64_t seq : stamps.seq) owner.emplace_back(seq, s.id);
    }
    std::sort(owner.begin(), owner.end());
    auto& column = out.sessions[r];
    column.reserve(result.match.pairs.size());
    for (const auto& pair : result.match.pairs) {
      const std::int64_t seq = result.cause_seq(pair);
      const auto found = std::lower_bound(owner.begin(), owner.end(), std::pair{seq, std::int64_t{0}});
      column.push_back(found != owner.end() && found->first == seq ? found->second : 0);
    }
  }
  return out;
}

}  // namespace m2mlat::analysis
