// Binding values to INSERT parameters and reading SELECT columns back, one function per table.
#include "m2mlat/store/rows.hpp"

#include <fmt/format.h>

#include <bit>

#include "m2mlat/core/error.hpp"
#include "m2mlat/store/rate_block.hpp"

namespace m2mlat::store::rows {

namespace {

// Reads a stored enum value, refusing one the schema does not define.
template <typename Enum>
Enum read_enum(const sqlite::Statement& row, int column, const std::string& path, std::string_view table,
               std::string_view name) {
  const std::int64_t value = row.column_int64(column);
  const auto candidate = static_cast<Enum>(value);
  if (value < 0 || value > 255 || !is_known(candidate)) {
    core::throw_data_error(
        {path, 0},
        fmt::format("table '{}': column '{}' holds {}, which is not a known value", table, name, value));
  }
  return candidate;
}

core::TimePoint read_time(const sqlite::Statement& row, int clock_column, const std::string& path,
                          std::string_view table) {
  const auto clock = read_enum<core::Clock>(row, clock_column, path, table, "clock");
  return core::TimePoint::from_ns(clock, row.column_int64(clock_column + 1));
}

std::int64_t to_column(core::Clock clock) { return static_cast<std::int64_t>(clock); }

}  // namespace

std::int64_t to_column(std::uint64_t value) { return std::bit_cast<std::int64_t>(value); }
std::uint64_t from_column(std::int64_t column) { return std::bit_cast<std::uint64_t>(column); }

bool is_known(core::Clock clock) {
  switch (clock) {
    case core::Clock::realtime:
    case core::Clock::monotonic:
    case core::Clock::boottime:
    case core::Clock::simulated: return true;
  }
  return false;
}

bool is_known(core::Edge edge) { return edge == core::Edge::rising || edge == core::Edge::falling; }

bool is_known(core::Role role) {
  return role == core::Role::cause || role == core::Role::effect || role == core::Role::observer;
}

void bind_session(sqlite::Statement& insert, const Session& session) {
  insert.bind(1, session.label);
  insert.bind(2, session.scenario);
  insert.bind(3, session.node);
  insert.bind(4, static_cast<std::int64_t>(session.role));
  insert.bind(5, session.config_json);
  insert.bind(6, to_column(session.start.clock()));
  insert.bind(7, session.start.ns());
  if (session.end) {
    insert.bind(8, to_column(session.end->clock()));
    insert.bind(9, session.end->ns());
  } else {
    insert.bind_null(8);
    insert.bind_null(9);
  }
  insert.bind(10, session.software_version);
}

std::string insert_events_sql(int rows) {
  std::string sql(kInsertEvent.substr(0, kInsertEvent.find("VALUES")));
  sql += "VALUES ";
  for (int r = 0; r < rows; ++r) {
    sql += r == 0 ? "(" : ", (";
    for (int p = 1; p <= 8; ++p) sql += fmt::format("{}?{}", p == 1 ? "" : ", ", r * 8 + p);
    sql += ")";
  }
  return sql;
}

void bind_event(sqlite::Statement& insert, std::int64_t session_id, const core::Event& event, int first) {
  insert.bind(first + 1, session_id);
  insert.bind(first + 2, event.channel);
  insert.bind(first + 3, static_cast<std::int64_t>(event.edge));
  insert.bind(first + 4, to_column(event.time.clock()));
  insert.bind(first + 5, event.time.ns());
  insert.bind(first + 6, to_column(event.seqno));
  insert.bind(first + 7, to_column(event.line_seqno));
  insert.bind(first + 8, static_cast<std::int64_t>(event.flags));
}

void bind_clock_sample(sqlite::Statement& insert, const ClockSample& sample) {
  insert.bind(1, sample.session_id);
  insert.bind(2, to_column(sample.time.clock()));
  insert.bind(3, sample.time.ns());
  insert.bind(4, sample.source);
  insert.bind(5, sample.offset_ns);
  insert.bind(6, sample.max_error_ns);
  insert.bind(7, sample.est_error_ns);
  insert.bind(8, std::int64_t{sample.synchronised ? 1 : 0});
  insert.bind(9, sample.detail_json);
}

void bind_loss(sqlite::Statement& insert, const Loss& loss) {
  insert.bind(1, loss.session_id);
  insert.bind(2, loss.channel);
  insert.bind(3, to_column(loss.detected_at.clock()));
  insert.bind(4, loss.detected_at.ns());
  insert.bind(5, to_column(loss.first_missing));
  insert.bind(6, to_column(loss.count));
  insert.bind(7, loss.kind);
}

Session read_session(const sqlite::Statement& row, const std::string& path) {
  Session session;
  session.id = row.column_int64(0);
  session.label = row.column_text(1);
  session.scenario = row.column_text(2);
  session.node = row.column_text(3);
  session.role = read_enum<core::Role>(row, 4, path, "sessions", "role");
  session.config_json = row.column_text(5);
  session.start = read_time(row, 6, path, "sessions");
  if (!row.column_is_null(8)) session.end = read_time(row, 8, path, "sessions");
  session.software_version = row.column_text(10);
  return session;
}

StoredEvent read_event(const sqlite::Statement& row, const std::string& path) {
  StoredEvent stored;
  stored.seq = row.column_int64(0);
  stored.session_id = row.column_int64(1);
  // Rows no m2mlat writes (a file edited by another tool) are refused, not passed on.
  const auto refuse = [&](std::string_view field, std::string_view what) {
    core::throw_data_error({path, 0},
                           fmt::format("table 'events' row seq {}: field '{}' {}", stored.seq, field, what));
  };
  if (row.column_is_null(2))  // the LEFT JOIN found no session
    refuse("session_id", fmt::format("names session {}, which does not exist", stored.session_id));
  core::Event& event = stored.event;
  event.node = row.column_text(2);
  event.channel = row.column_text(3);
  if (event.channel.empty()) refuse("channel", "is empty");
  if (const auto flags = row.column_int64(9); flags < 0 || flags > 0xFFFF'FFFF)
    refuse("flags", fmt::format("holds {} (expected 0 to 4294967295)", flags));
  event.edge = read_enum<core::Edge>(row, 4, path, "events", "edge");
  event.time = read_time(row, 5, path, "events");
  event.seqno = from_column(row.column_int64(7));
  event.line_seqno = from_column(row.column_int64(8));
  event.flags = static_cast<std::uint32_t>(row.column_int64(9));  // checked above
  return stored;
}

ClockSample read_clock_sample(const sqlite::Statement& row, const std::string& path) {
  ClockSample sample;
  sample.session_id = row.column_int64(0);
  sample.time = read_time(row, 1, path, "clock_samples");
  sample.source = row.column_text(3);
  sample.offset_ns = row.column_int64(4);
  sample.max_error_ns = row.column_int64(5);
  sample.est_error_ns = row.column_int64(6);
  sample.synchronised = row.column_int64(7) != 0;
  sample.detail_json = row.column_text(8);
  return sample;
}

Loss read_loss(const sqlite::Statement& row, const std::string& path) {
  Loss loss;
  loss.session_id = row.column_int64(0);
  loss.channel = row.column_text(1);
  loss.detected_at = read_time(row, 2, path, "losses");
  loss.first_missing = from_column(row.column_int64(4));
  loss.count = from_column(row.column_int64(5));
  loss.kind = row.column_text(6);
  return loss;
}

void bind_rate_block(sqlite::Statement& insert, const RateBlock& block) {
  insert.bind(1, block.session_id);
  insert.bind(2, block.channel);
  insert.bind(3, to_column(block.clock));
  insert.bind_double(4, block.counts_per_deg_s);
  insert.bind(5, to_column(block.first_index));
  insert.bind(6, static_cast<std::int64_t>(block.samples.size()));
  insert.bind(7, block.samples.front().time_ns);
  insert.bind(8, block.samples.back().time_ns);
  insert.bind(9, rate_block::kLayout);
  insert.bind_blob(10, rate_block::encode(block.samples));
}

StoredRateBlock read_rate_block(const sqlite::Statement& row, const std::string& path) {
  StoredRateBlock out;
  out.id = row.column_int64(8);
  RateBlock& block = out.block;
  block.session_id = row.column_int64(0);
  block.channel = row.column_text(1);
  block.clock = read_enum<core::Clock>(row, 2, path, "rate_blocks", "clock");
  block.counts_per_deg_s = row.column_double(3);
  block.first_index = from_column(row.column_int64(4));
  block.samples = rate_block::decode(row.column_blob(7), row.column_int64(6), row.column_int64(5),
                                     fmt::format("{}: table 'rate_blocks' row id {}", path, out.id));
  return out;
}

void bind_marker(sqlite::Statement& insert, const MarkerRecord& m) {
  insert.bind(1, m.session_id);
  insert.bind(2, m.name);
  insert.bind(3, to_column(m.time.clock()));
  insert.bind(4, m.time.ns());
  insert.bind(5, m.source);
  if (m.uncertainty_ns) insert.bind(6, *m.uncertainty_ns);
  else insert.bind_null(6);
  insert.bind(7, m.key);
  if (m.sender_ns) insert.bind(8, *m.sender_ns);
  else insert.bind_null(8);
  insert.bind(9, m.origin);
}

StoredMarker read_marker(const sqlite::Statement& row, const std::string& path) {
  StoredMarker out;
  out.id = row.column_int64(9);
  MarkerRecord& m = out.marker;
  m.session_id = row.column_int64(0);
  m.name = row.column_text(1);
  m.time = read_time(row, 2, path, "markers");
  m.source = row.column_text(4);
  if (!row.column_is_null(5)) m.uncertainty_ns = row.column_int64(5);
  m.key = row.column_text(6);
  if (!row.column_is_null(7)) m.sender_ns = row.column_int64(7);
  m.origin = row.column_text(8);
  return out;
}

}  // namespace m2mlat::store::rows
