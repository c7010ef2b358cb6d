#include "m2mlat/markers/one_way.hpp"

#include <algorithm>
#include <string_view>
#include <unordered_map>
#include <unordered_set>

#include "m2mlat/stats/quantile.hpp"

namespace m2mlat::markers {

OneWayMatch match_one_way(std::span<const Marker> sender, std::span<const Marker> receiver) {
  OneWayMatch result;
  std::unordered_map<std::string_view, const Marker*> arrivals;
  arrivals.reserve(receiver.size());
  for (const auto& marker : receiver)
    if (!arrivals.emplace(marker.key, &marker).second) ++result.repeated_keys;
  std::unordered_set<std::string_view> sent;
  sent.reserve(sender.size());
  for (const auto& marker : sender) {
    if (!sent.insert(marker.key).second) {
      ++result.repeated_keys;
      continue;
    }
    const auto found = arrivals.find(marker.key);
    if (found == arrivals.end()) {
      ++result.sender_only;
      continue;
    }
    const Marker& arrival = *found->second;
    OneWay command;
    command.key = marker.key;
    command.sent_ns = marker.time.ns();
    command.received_ns = arrival.time.ns();
    command.one_way_ns = command.received_ns - command.sent_ns;
    if (marker.sender_time) command.sender_ns = marker.sender_time->ns();
    command.sent_origin = marker.origin;
    command.received_origin = arrival.origin;
    result.commands.push_back(std::move(command));
  }
  result.receiver_only = arrivals.size() - (result.commands.size());
  return result;
}

OneWaySummary summarize(const OneWayMatch& match) {
  std::vector<std::int64_t> times;
  times.reserve(match.commands.size());
  for (const auto& command : match.commands) times.push_back(command.one_way_ns);
  std::sort(times.begin(), times.end());
  OneWaySummary summary;
  summary.n = times.size();
  summary.median_ns = stats::quantile(times, 0.5);
  summary.p95_ns = stats::quantile(times, 0.95);
  return summary;
}

}  // namespace m2mlat::markers
