// The agent API's wire format, version 1 (docs/api.md): JSON objects for sessions, events, clock
// samples, losses, blocks of raw rate samples and the agent's status, kept apart from the in-memory types so either can change
// without the other. The server encodes with these; the coordinator's client decodes with them.
// Decoding refuses a missing, mistyped or out-of-range field with core::Error(data) naming `where`
// (e.g. "http://10.0.0.2:8470/v1/events line 12") and the field.
#pragma once

#include <cstddef>
#include <cstdint>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "m2mlat/store/records.hpp"

namespace m2mlat::net {

inline constexpr std::string_view kApiName = "m2mlat-agent/1";
inline constexpr std::string_view kApiHeader = "X-M2mlat-Api";  // value "1" on every response
inline constexpr std::string_view kLastSeqHeader = "X-M2mlat-Last-Seq";
// Rate blocks per /v1/rate-blocks page at most, whatever the limit asked: a block holds up to 4096
// samples, about 180 KB of JSON, so a page stays under 3 MB.
inline constexpr std::size_t kMaxRateBlocksPerPage = 16;

struct ChannelStatus {
  std::string name;
  std::uint64_t events = 0;
  std::uint64_t suppressed = 0;
  std::uint64_t lost = 0;
  std::optional<std::int64_t> last_ns;  // the last stored event's time, ns on the session's clock
  friend bool operator==(const ChannelStatus&, const ChannelStatus&) = default;
};

// The agent's software-marker port (`--mark-port`): what it stored and refused since it started.
struct MarkStatus {
  std::string address;  // where it listens, "127.0.0.1:7010"
  std::string stamps;   // who stamps arrivals: "kernel" (SO_TIMESTAMPNS) or "receiver" (clock_gettime)
  std::uint64_t stored = 0;
  // Refused datagrams by reason (markers::kMarkReasons, "session": none open, "store": not stored),
  // in that order, only reasons seen; and the last refusal's text, for the operator.
  std::vector<std::pair<std::string, std::uint64_t>> rejected;
  std::string last_rejection;
  friend bool operator==(const MarkStatus&, const MarkStatus&) = default;
};

struct Status {
  std::string api{kApiName};
  std::string software_version;
  std::string node;
  core::Role role = core::Role::observer;
  std::string store_id;
  std::optional<store::Session> session;  // the open session, if any
  std::vector<ChannelStatus> channels;
  std::uint64_t events = 0;                 // stored since the agent started
  std::uint64_t lost = 0;                   // reported lost since the agent started
  std::uint64_t dropped = 0;                // seen while no session was open (not stored)
  std::int64_t last_seq = 0;                // the store's last committed seq
  std::optional<store::ClockSample> clock;  // the latest clock sample
  std::int64_t started_ns = 0;              // CLOCK_REALTIME when the agent started
  std::int64_t now_ns = 0;                  // CLOCK_REALTIME when the status was made
  std::optional<MarkStatus> marks;          // the marker port, when the agent has one
  friend bool operator==(const Status&, const Status&) = default;
};

nlohmann::json to_json(const store::Session& session);
nlohmann::json to_json(const store::StoredEvent& event);  // node and role are the session's: not sent
// The same event as one line of JSON text, appended to `out`: exactly the bytes of
// to_json(event).dump() (keys in order, invalid UTF-8 replaced), without building a JSON value, so
// that an agent serving a catch-up of a million events spends its time on the store, not on the heap.
void append_json(std::string& out, const store::StoredEvent& event);
nlohmann::json to_json(const store::StoredClockSample& sample);
nlohmann::json to_json(const store::StoredLoss& loss);
// A block of raw rate samples: its fields and "samples": [[time_ns, bound_ns, x, y, z], ...].
nlohmann::json to_json(const store::StoredRateBlock& block);
nlohmann::json to_json(const store::StoredMarker& marker);
nlohmann::json to_json(const Status& status);

store::Session session_from_json(const nlohmann::json& json, std::string_view where);
// The inverse of append_json, for the agent's own text only: every field in its order, a channel
// name without escapes, integers without leading zeros. Anything else, valid or not, gives nullopt:
// decode it with event_from_json, which also names what is wrong. The node is left empty (it is
// the session's). A coordinator catching up a million events spends its time on storing them.
std::optional<store::StoredEvent> parse_canonical_event(std::string_view line);
// The event's node and role come from its session (looked up by the caller): pass them in.
store::StoredEvent event_from_json(const nlohmann::json& json, std::string_view where,
                                   const std::string& node, core::Role role);
store::StoredClockSample clock_sample_from_json(const nlohmann::json& json, std::string_view where);
store::StoredLoss loss_from_json(const nlohmann::json& json, std::string_view where);
// Refuses a block of no or more than rate_block::kMaxSamples samples, a sample that is not five
// integers in range (bound >= 0 in int32, x, y, z in int16) or a stamp before the one before it.
store::StoredRateBlock rate_block_from_json(const nlohmann::json& json, std::string_view where);
store::StoredMarker marker_from_json(const nlohmann::json& json, std::string_view where);
Status status_from_json(const nlohmann::json& json, std::string_view where);

// {"error":{"status":N,"message":"..."}}
std::string error_body(int status, std::string_view message);

}  // namespace m2mlat::net
