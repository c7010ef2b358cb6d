// The values the store takes and gives back: sessions, stored events, clock samples, losses, blocks
// of raw rate samples, and the options of a store. These are the store's API types; how they map to SQLite rows is in
// rows.hpp and the schema in schema.cpp, so the file format can change without touching them.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "m2mlat/core/event.hpp"
#include "m2mlat/core/rate_sample.hpp"
#include "m2mlat/core/time.hpp"

namespace m2mlat::store {

// What a commit promises about surviving a crash.
enum class Durability : std::uint8_t {
  full,    // WAL + synchronous=FULL: every commit is fsynced; survives power loss
  normal,  // WAL + synchronous=NORMAL: survives a process crash (kill -9); a power loss may lose
           // the last commits, never the file
  off,     // WAL + synchronous=OFF: survives a process crash; a power loss may corrupt the file
};
std::string_view to_string(Durability durability);
Durability parse_durability(std::string_view text);  // "full" | "normal" | "off"; throws Error(usage)

struct Options {
  Durability durability = Durability::normal;
  bool read_only = false;      // no writes; the store must exist and be at the current schema version
  bool create = true;          // create the file if it does not exist (ignored when read_only)
  int busy_timeout_ms = 5000;  // how long to wait for another process's lock, milliseconds
};

// One recording run of one node: the events it captured belong to it.
struct Session {
  std::int64_t id = 0;   // assigned by the store; ignored by begin_session
  std::string label;     // free text chosen by the user, e.g. "run-12"
  std::string scenario;  // free text, e.g. "urban-30kmh"
  std::string node;      // the board that recorded, e.g. "vehicle"; must not be empty
  core::Role role = core::Role::observer;
  std::string config_json = "{}";  // the configuration in force; must be valid JSON
  core::TimePoint start;
  std::optional<core::TimePoint> end;  // empty while the session is open; same clock as start
  std::string software_version;        // the m2mlat version that recorded; empty = this build's

  friend bool operator==(const Session&, const Session&) = default;
};

// The configuration key (an integer, ns) of the largest half-width of an LED session's writes: each
// LED event's time is the middle of the clock readings before and after its write, so the switch lies
// within +-this of it. `m2mlat led` sets it when the session ends (Store::end_session); the chains'
// glass-to-glass uncertainty uses it for every write of the session (analysis/store_chains.hpp).
inline constexpr const char* kConfigLedBound = "led_bound_ns";

// The scenario of a session begun without one (`record`, `agent` and the API's POST /v1/sessions with
// no scenario: e.g. the agent's first session, recording before `collect --start-session` names one).
// An empty name would make a scenario that no --scenario can choose and no table can show.
inline constexpr const char* kUnnamedScenario = "unnamed";

// An event as stored: its store-wide sequence number (increasing, never reused) and its session.
// event.node is the session's node.
struct StoredEvent {
  std::int64_t seq = 0;
  std::int64_t session_id = 0;
  core::Event event;

  friend bool operator==(const StoredEvent&, const StoredEvent&) = default;
};

// One reading of a board's clock state, e.g. from adjtimex(2) or chronyc tracking.
struct ClockSample {
  std::int64_t session_id = 0;
  core::TimePoint time;           // when the sample was taken
  std::string source;             // "adjtimex", "chrony", "ptp", "sim", ...: lower-case letters, digits, '_'
  std::int64_t offset_ns = 0;     // estimated offset from the reference, ns (positive = ahead)
  std::int64_t max_error_ns = 0;  // maximum error bound, ns
  std::int64_t est_error_ns = 0;  // estimated error, ns
  bool synchronised = false;
  std::string detail_json = "{}";  // source-specific fields; must be valid JSON

  friend bool operator==(const ClockSample&, const ClockSample&) = default;
};

// Events known to be missing: a gap in the kernel's sequence numbers, a lost buffer, a restart.
struct Loss {
  std::int64_t session_id = 0;
  std::string channel;  // the channel the gap was seen on; may be empty for a node-wide loss
  core::TimePoint detected_at;
  std::uint64_t first_missing = 0;  // first missing sequence number (of the kind's counter)
  std::uint64_t count = 0;          // how many are missing; at least 1
  std::string kind;                 // one of kLossKinds

  friend bool operator==(const Loss&, const Loss&) = default;
};

// The kinds of loss the store accepts (stored by name: keep the names stable).
// "missed_period" and "i2c_error" are a gyroscope's: first_missing is the number (in read order) the
// next sample read gets, count how many periods went by without a read / failed transfers.
inline constexpr std::string_view kLossKinds[] = {"seqno_gap", "line_seqno_gap", "kmsg_gap", "overflow",
                                                  "restart",   "missed_period",  "i2c_error"};

// A run of one gyroscope channel's raw samples of one session, stored as one row (rate_block.hpp
// has the BLOB's layout). A trace is kept as consecutive blocks.
struct RateBlock {
  std::int64_t session_id = 0;
  std::string channel;  // e.g. "gyro"; must not be empty
  core::Clock clock = core::Clock::realtime;  // the clock of every sample's stamp
  double counts_per_deg_s = 131.0;            // the chip's scale, counts per deg/s; > 0
  // The number of the block's first sample in read order (0 = the session's first on this channel);
  // sample k of the block is number first_index + k. A jump to the next block's first_index shows
  // samples left out by a keep window (or a block lost); periods without a read are losses.
  std::uint64_t first_index = 0;
  std::vector<core::RateSample> samples;  // in time order; 1 to rate_block::kMaxSamples
};

// One stored raw trace: a session's channel of rate samples, and how many samples it holds.
struct RateChannel {
  std::int64_t session_id = 0;
  std::string node;     // the session's node
  std::string channel;
  std::int64_t samples = 0;
  friend bool operator==(const RateChannel&, const RateChannel&) = default;
};

// A block with its row id in the store that holds it (increasing, never reused).
struct StoredRateBlock {
  std::int64_t id = 0;
  RateBlock block;
};

// A marker of one session: a named point of a command's way through the pipeline (docs/markers.md),
// the stored form of markers::Marker. The node is the session's.
struct MarkerRecord {
  std::int64_t session_id = 0;
  std::string name;      // the point ("packet", "planner_out", ...); must not be empty
  core::TimePoint time;  // its stamp, ns on its clock (CLOCK_REALTIME for every kind m2mlat makes)
  // Who took the stamp (markers::StampSource's name: "kernel", "receiver", "bag_log", ...): lower-case
  // letters, digits and '_', not empty.
  std::string source;
  std::optional<std::int64_t> uncertainty_ns;  // the stamp's uncertainty (ns, k = 1) when known; >= 0
  std::string key;                             // the command's key across boards; may be empty
  std::optional<std::int64_t> sender_ns;       // the sender's own CLOCK_REALTIME stamp, ns, if it gave one
  std::string origin;                          // where it was seen (a datagram's sender address, a file)

  friend bool operator==(const MarkerRecord&, const MarkerRecord&) = default;
};

// A marker with its row id in the store that holds it (increasing, never reused).
struct StoredMarker {
  std::int64_t id = 0;
  MarkerRecord marker;
  friend bool operator==(const StoredMarker&, const StoredMarker&) = default;
};

// Everything one commit writes, all or nothing.
struct Batch {
  std::int64_t session_id = 0;      // the session the events belong to
  std::vector<core::Event> events;  // every event's node must be the session's node
  std::vector<Loss> losses;
  std::vector<ClockSample> clock_samples;
  std::vector<RateBlock> rate_blocks;  // each names its own (open) session
  std::vector<MarkerRecord> markers;   // each names its own (open) session
};

// The store-wide sequence numbers a commit gave its events; both 0 when it had none.
struct AppendResult {
  std::int64_t first_seq = 0;
  std::int64_t last_seq = 0;
  friend bool operator==(const AppendResult&, const AppendResult&) = default;
};

// Restricts an event read; an empty field matches everything.
struct EventFilter {
  std::optional<std::int64_t> session_id;
  std::optional<std::string> node;
  std::optional<std::string> channel;
  std::optional<core::Edge> edge;
};

// Columns of one event set in time order, for pairing many events without building an Event each.
struct Timestamps {
  core::Clock clock = core::Clock::realtime;
  std::vector<std::int64_t> seq;   // store sequence number of each event
  std::vector<std::int64_t> t_ns;  // its timestamp, ns on `clock`
};

// A clock sample or a loss with its row id in the store that holds it (increasing, never reused):
// what the agent serves and a campaign store resumes from.
struct StoredClockSample {
  std::int64_t id = 0;
  ClockSample sample;
  friend bool operator==(const StoredClockSample&, const StoredClockSample&) = default;
};
struct StoredLoss {
  std::int64_t id = 0;
  Loss loss;
  friend bool operator==(const StoredLoss&, const StoredLoss&) = default;
};

// How far a campaign store has taken in one origin store (an agent's or a board's file): the
// largest origin event seq, clock-sample id and loss id it holds. 0 = nothing yet.
struct IngestCursor {
  std::int64_t events = 0;
  std::int64_t clock_samples = 0;
  std::int64_t losses = 0;
  std::int64_t rate_blocks = 0;
  std::int64_t markers = 0;
  friend bool operator==(const IngestCursor&, const IngestCursor&) = default;
};

// What an origin store had, as read from it (agent API or file). Ids, seqs and session ids are the
// origin's. Items at or below the campaign store's cursor for this origin are skipped, so giving
// the same batch twice changes nothing.
struct IngestBatch {
  std::string origin;                 // the origin's store_id(); must not be empty
  std::vector<Session> sessions;      // every origin session the items below name (ended or not),
                                      // and any whose end became known; ids are the origin's
  std::vector<StoredEvent> events;    // in origin seq order
  std::vector<StoredClockSample> clock_samples;  // in origin id order
  std::vector<StoredLoss> losses;                // in origin id order
  std::vector<StoredRateBlock> rate_blocks;      // in origin id order
  std::vector<StoredMarker> markers;             // in origin id order
};

}  // namespace m2mlat::store
