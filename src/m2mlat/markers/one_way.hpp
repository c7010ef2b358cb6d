// Commands matched across two captures by their key: each command's one-way time, from the
// sender's capture to the receiver's (both CLOCK_REALTIME of synchronised boards, int64 ns), and
// the sender's own stamp to each capture.
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "m2mlat/markers/marker.hpp"

namespace m2mlat::markers {

struct OneWay {
  std::string key;
  std::int64_t sent_ns = 0;      // the sender's capture time, ns
  std::int64_t received_ns = 0;  // the receiver's capture time, ns
  std::int64_t one_way_ns = 0;   // received_ns - sent_ns, exactly
  std::optional<std::int64_t> sender_ns;  // the sender's stamp in the command (the sender's marker)
  std::string sent_origin;
  std::string received_origin;
};

struct OneWayMatch {
  std::vector<OneWay> commands;        // in the order of the sender's capture
  std::uint64_t sender_only = 0;       // keys the receiver never saw (lost, or outside its capture)
  std::uint64_t receiver_only = 0;     // keys the sender's capture does not have
  std::uint64_t repeated_keys = 0;     // later markers with a key already seen on the same side (ignored)
};

// n, median and 95th percentile (type 7, docs/statistics.md) of the one-way times, ns; NaN when n = 0.
struct OneWaySummary {
  std::size_t n = 0;
  double median_ns = 0;
  double p95_ns = 0;
};
OneWaySummary summarize(const OneWayMatch& match);

// A key seen twice on one side keeps its first marker (a command's first send and first arrival).
OneWayMatch match_one_way(std::span<const Marker> sender, std::span<const Marker> receiver);

}  // namespace m2mlat::markers
