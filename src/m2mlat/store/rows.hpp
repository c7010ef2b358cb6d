// The explicit mapping between SQLite rows and the store's values (records.hpp, core::Event).
//
// The schema is kept apart from the in-memory types: every column is bound and read here, by
// name and position, so a change of either side shows up in one file. Decoding checks stored enum
// values, so a file edited by another tool gives a clear error instead of an invalid enum.
#pragma once

#include <cstdint>
#include <string>
#include <string_view>

#include "m2mlat/core/event.hpp"
#include "m2mlat/core/time.hpp"
#include "m2mlat/store/records.hpp"
#include "m2mlat/store/sqlite.hpp"

namespace m2mlat::store::rows {

// uint64 counters are stored as the int64 with the same bits (SQLite integers are signed 64-bit),
// so every value, 2^64-1 included, reads back unchanged.
std::int64_t to_column(std::uint64_t value);
std::uint64_t from_column(std::int64_t column);

// Whether a value is one the schema defines (a cast from an integer may not be).
bool is_known(core::Clock clock);
bool is_known(core::Edge edge);
bool is_known(core::Role role);

// SELECT lists, in the order the read_* functions expect them.
inline constexpr std::string_view kSessionColumns =
    "id, label, scenario, node, role, config_json, start_clock, start_ns, end_clock, end_ns, "
    "software_version";
inline constexpr std::string_view kEventColumns =  // events e JOIN sessions s
    "e.seq, e.session_id, s.node, e.channel, e.edge, e.clock, e.t_ns, e.seqno, e.line_seqno, e.flags";
inline constexpr std::string_view kClockSampleColumns =
    "session_id, clock, t_ns, source, offset_ns, max_error_ns, est_error_ns, synchronised, detail_json";
inline constexpr std::string_view kLossColumns =
    "session_id, channel, clock, t_ns, first_missing, count, kind";
inline constexpr std::string_view kRateBlockColumns =
    "session_id, channel, clock, counts_per_deg_s, first_index, count, layout, samples, id";
inline constexpr std::string_view kMarkerColumns =
    "session_id, name, clock, t_ns, source, uncertainty_ns, key, sender_ns, origin, id";

// INSERT statements whose parameters the bind_* functions fill.
inline constexpr std::string_view kInsertSession =
    "INSERT INTO sessions (label, scenario, node, role, config_json, start_clock, start_ns, end_clock, "
    "end_ns, "
    "software_version) VALUES (?1, ?2, ?3, ?4, ?5, ?6, ?7, ?8, ?9, ?10)";
inline constexpr std::string_view kInsertEvent =
    "INSERT INTO events (session_id, channel, edge, clock, t_ns, seqno, line_seqno, flags) "
    "VALUES (?1, ?2, ?3, ?4, ?5, ?6, ?7, ?8)";
// kInsertEvent for `rows` events in one statement (parameters 8 per row, in order): a recorder's
// batch is inserted kEventsPerInsert rows at a time, which saves SQLite's per-statement work (cursors
// on the table and its indexes opened, the statement run and reset) on all but one row in each.
inline constexpr int kEventsPerInsert = 32;
std::string insert_events_sql(int rows);
inline constexpr std::string_view kInsertClockSample =
    "INSERT INTO clock_samples (session_id, clock, t_ns, source, offset_ns, max_error_ns, est_error_ns, "
    "synchronised, detail_json) VALUES (?1, ?2, ?3, ?4, ?5, ?6, ?7, ?8, ?9)";
inline constexpr std::string_view kInsertLoss =
    "INSERT INTO losses (session_id, channel, clock, t_ns, first_missing, count, kind) "
    "VALUES (?1, ?2, ?3, ?4, ?5, ?6, ?7)";
inline constexpr std::string_view kInsertRateBlock =
    "INSERT INTO rate_blocks (session_id, channel, clock, counts_per_deg_s, first_index, count, first_ns, "
    "last_ns, layout, samples) VALUES (?1, ?2, ?3, ?4, ?5, ?6, ?7, ?8, ?9, ?10)";
inline constexpr std::string_view kInsertMarker =
    "INSERT INTO markers (session_id, name, clock, t_ns, source, uncertainty_ns, key, sender_ns, origin) "
    "VALUES (?1, ?2, ?3, ?4, ?5, ?6, ?7, ?8, ?9)";

// `software_version` is bound as given; the caller fills an empty one.
void bind_session(sqlite::Statement& insert, const Session& session);
// Parameters first + 1 .. first + 8 (first = 8 * row for the row of a multi-row insert).
void bind_event(sqlite::Statement& insert, std::int64_t session_id, const core::Event& event, int first = 0);
void bind_clock_sample(sqlite::Statement& insert, const ClockSample& sample);
void bind_loss(sqlite::Statement& insert, const Loss& loss);
// The samples must be 1 to rate_block::kMaxSamples, in time order (validate::rate_block).
void bind_rate_block(sqlite::Statement& insert, const RateBlock& block);
void bind_marker(sqlite::Statement& insert, const MarkerRecord& marker);

// `path` names the store in errors about values no m2mlat writes.
Session read_session(const sqlite::Statement& row, const std::string& path);
StoredEvent read_event(const sqlite::Statement& row, const std::string& path);
ClockSample read_clock_sample(const sqlite::Statement& row, const std::string& path);
Loss read_loss(const sqlite::Statement& row, const std::string& path);
// Columns kRateBlockColumns; decodes the BLOB, a damaged one reported naming the table and row.
StoredRateBlock read_rate_block(const sqlite::Statement& row, const std::string& path);
// Columns kMarkerColumns.
StoredMarker read_marker(const sqlite::Statement& row, const std::string& path);

}  // namespace m2mlat::store::rows
