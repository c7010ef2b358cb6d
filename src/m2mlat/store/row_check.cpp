// The schema's rules as queries (see row_check.hpp). Keep them in step with the CHECK clauses and
// references of schema.cpp; a rule that a valid row could break would stop every analysis, so each
// one is exactly the negation of a clause there.
#include "m2mlat/store/row_check.hpp"

#include <fmt/format.h>

#include <span>
#include <string>
#include <string_view>

#include "m2mlat/core/error.hpp"

namespace m2mlat::store::row_check {

namespace {

struct Rule {
  std::string_view field;     // the column named in the message
  std::string_view broken;    // SQL: true for a row that breaks the rule
  std::string_view expected;  // for the message
};

struct Table {
  std::string_view name;
  std::string_view key;  // the column that names a row in the message
  std::span<const Rule> rules;
};

constexpr std::string_view kClockBroken = "typeof(clock) <> 'integer' OR clock NOT BETWEEN 0 AND 3";

constexpr Rule kSessionRules[] = {
    {"node", "node = ''", "not empty"},
    {"role", "typeof(role) <> 'integer' OR role NOT BETWEEN 0 AND 2", "0, 1 or 2"},
    {"start_clock", "typeof(start_clock) <> 'integer' OR start_clock NOT BETWEEN 0 AND 3", "0 to 3"},
    {"start_ns", "typeof(start_ns) <> 'integer'", "an integer"},
    {"end_clock",
     "end_clock IS NOT NULL AND (typeof(end_clock) <> 'integer' OR end_clock NOT BETWEEN 0 AND 3)",
     "0 to 3 or NULL"},
    {"end_ns",
     "(end_clock IS NULL) <> (end_ns IS NULL) OR (end_ns IS NOT NULL AND typeof(end_ns) <> 'integer')",
     "an integer, NULL exactly when end_clock is"},
};
constexpr Rule kEventRules[] = {
    {"session_id", "session_id NOT IN (SELECT id FROM sessions)", "an existing session"},
    {"channel", "channel = ''", "not empty"},
    {"edge", "typeof(edge) <> 'integer' OR edge NOT IN (0, 1)", "0 or 1"},
    {"clock", kClockBroken, "0 to 3"},
    {"t_ns", "typeof(t_ns) <> 'integer'", "an integer"},
    {"seqno", "typeof(seqno) <> 'integer'", "an integer"},
    {"line_seqno", "typeof(line_seqno) <> 'integer'", "an integer"},
    {"flags", "typeof(flags) <> 'integer' OR flags NOT BETWEEN 0 AND 4294967295", "0 to 4294967295"},
};
constexpr Rule kClockSampleRules[] = {
    {"session_id", "session_id NOT IN (SELECT id FROM sessions)", "an existing session"},
    {"clock", kClockBroken, "0 to 3"},
    {"t_ns", "typeof(t_ns) <> 'integer'", "an integer"},
    {"source", "source = ''", "not empty"},
    {"synchronised", "typeof(synchronised) <> 'integer' OR synchronised NOT IN (0, 1)", "0 or 1"},
};
constexpr Rule kLossRules[] = {
    {"session_id", "session_id NOT IN (SELECT id FROM sessions)", "an existing session"},
    {"clock", kClockBroken, "0 to 3"},
    {"t_ns", "typeof(t_ns) <> 'integer'", "an integer"},
    {"count", "typeof(count) <> 'integer' OR count = 0", "a non-zero integer"},
    {"kind",
     "kind NOT IN ('seqno_gap', 'line_seqno_gap', 'kmsg_gap', 'overflow', 'restart', 'missed_period', "
     "'i2c_error')",
     "a known loss kind"},
};
constexpr Rule kRateBlockRules[] = {
    {"session_id", "session_id NOT IN (SELECT id FROM sessions)", "an existing session"},
    {"channel", "channel = ''", "not empty"},
    {"clock", kClockBroken, "0 to 3"},
    {"counts_per_deg_s", "typeof(counts_per_deg_s) NOT IN ('real', 'integer') OR counts_per_deg_s <= 0",
     "a number above 0"},
    {"first_index", "typeof(first_index) <> 'integer' OR first_index < 0", "an integer >= 0"},
    {"count", "typeof(count) <> 'integer' OR count NOT BETWEEN 1 AND 4096", "1 to 4096"},
    {"first_ns", "typeof(first_ns) <> 'integer'", "an integer"},
    {"last_ns", "typeof(last_ns) <> 'integer' OR last_ns < first_ns", "an integer >= first_ns"},
    {"layout", "typeof(layout) <> 'integer' OR layout <> 1", "1 (the layout this m2mlat reads)"},
    {"samples", "typeof(samples) <> 'blob' OR length(samples) <> 18 * count", "a BLOB of 18 bytes a sample"},
};
constexpr Rule kMarkerRules[] = {
    {"session_id", "session_id NOT IN (SELECT id FROM sessions)", "an existing session"},
    {"name", "name = ''", "not empty"},
    {"clock", kClockBroken, "0 to 3"},
    {"t_ns", "typeof(t_ns) <> 'integer'", "an integer"},
    {"source", "source = ''", "not empty"},
    {"uncertainty_ns",
     "uncertainty_ns IS NOT NULL AND (typeof(uncertainty_ns) <> 'integer' OR uncertainty_ns < 0)",
     "an integer >= 0 or NULL"},
    {"sender_ns", "sender_ns IS NOT NULL AND typeof(sender_ns) <> 'integer'", "an integer or NULL"},
};

constexpr Rule kEventSpanRules[] = {
    {"session_id", "session_id NOT IN (SELECT id FROM sessions)", "an existing session"},
    {"channel", "channel = ''", "not empty"},
    {"clock", kClockBroken, "0 to 3"},
    {"first_seq", "typeof(first_seq) <> 'integer' OR first_seq < 1", "an integer >= 1"},
    {"last_seq", "typeof(last_seq) <> 'integer' OR last_seq < first_seq", "an integer >= first_seq"},
    {"first_ns", "typeof(first_ns) <> 'integer'", "an integer"},
    {"last_ns", "typeof(last_ns) <> 'integer' OR last_ns < first_ns", "an integer >= first_ns"},
    {"count", "typeof(count) <> 'integer' OR count NOT BETWEEN 1 AND last_seq - first_seq + 1",
     "1 to the span's seq range"},
};

constexpr Table kEvents = {"events", "seq", kEventRules};
// The tables check_tables scans whole.
constexpr Table kTables[] = {
    {"sessions", "id", kSessionRules}, {"clock_samples", "id", kClockSampleRules},
    {"losses", "id", kLossRules},      {"rate_blocks", "id", kRateBlockRules},
    {"markers", "id", kMarkerRules},   {"event_spans", "id", kEventSpanRules},
};

// The first row of `table` breaking a rule, and the rule's index: one scan (of the rows `where`
// selects), the CASE naming the first rule a row breaks.
std::string broken_row_sql(const Table& table, std::string_view where) {
  std::string which = "CASE";
  int index = 0;
  for (const Rule& rule : table.rules) which += fmt::format(" WHEN {} THEN {}", rule.broken, index++);
  which += " END";
  return fmt::format("SELECT {}, {} AS rule FROM {} WHERE {} rule IS NOT NULL LIMIT 1", table.key, which,
                     table.name, where);
}

// Throws for the row of `table` with key `key` that breaks rule `rule_index`, showing its value.
[[noreturn]] void refuse_row(sqlite::Database& db, const Table& table, std::int64_t key,
                             std::int64_t rule_index) {
  const Rule& rule = table.rules[static_cast<std::size_t>(rule_index)];
  sqlite::Statement value(
      db, fmt::format("SELECT quote({}) FROM {} WHERE {} = ?1", rule.field, table.name, table.key));
  value.bind(1, key);
  const std::string shown = value.step() ? std::string(value.column_text(0)) : "?";
  core::throw_data_error({db.path(), 0},
                         fmt::format("table '{}' row {} {}: field '{}' holds {} (expected {}): the file "
                                     "breaks the store's schema (written or edited by another tool?)",
                                     table.name, table.key, key, rule.field, shown, rule.expected));
}

}  // namespace

void check_tables(sqlite::Database& db) {
  for (const Table& table : kTables) {
    sqlite::Statement query(db, broken_row_sql(table, ""));
    if (query.step()) refuse_row(db, table, query.column_int64(0), query.column_int64(1));
  }
}

// Every read finds events through their spans (event_spans.hpp), which m2mlat writes in the
// transaction of the events they count: an event another tool inserted without one, or deleted
// under one, would be left out of a read, or missed, without a word. So a range's events are
// counted (the rowid range's b-tree cells walked without decoding a row) against its spans' sum.
EventCheck::EventCheck(sqlite::Database& db)
    : db_(db),
      rules_(db, broken_row_sql(kEvents, "seq BETWEEN ?1 AND ?2 AND")),
      count_(db, "SELECT count(*) FROM events WHERE seq BETWEEN ?1 AND ?2"),
      between_(db, "SELECT seq FROM events WHERE seq > ?1 AND seq < ?2 ORDER BY seq LIMIT 1") {}

void EventCheck::check(std::int64_t first, std::int64_t last, std::int64_t spanned) {
  rules_.bind(1, first);
  rules_.bind(2, last);
  const bool broken = rules_.step();
  const std::int64_t key = broken ? rules_.column_int64(0) : 0, rule = broken ? rules_.column_int64(1) : 0;
  rules_.reset();
  if (broken) refuse_row(db_, kEvents, key, rule);
  if (count(first, last) != spanned) refuse_count(first, last, spanned, "");
}

std::optional<std::int64_t> EventCheck::first_between(std::int64_t after, std::int64_t before) {
  between_.bind(1, after);
  between_.bind(2, before);
  std::optional<std::int64_t> seq;
  if (between_.step()) seq = between_.column_int64(0);
  between_.reset();
  return seq;
}

void EventCheck::refuse_count(std::int64_t first, std::int64_t last, std::int64_t spanned,
                              std::string_view why) {
  core::throw_data_error(
      {db_.path(), 0}, fmt::format("table 'events' holds {} rows, its spans (table 'event_spans') count {}, "
                                   "from seq {} to {}{}: the file breaks the store's schema (written or "
                                   "edited by another tool?)",
                                   count(first, last), spanned, first, last, why));
}

std::int64_t EventCheck::count(std::int64_t first, std::int64_t last) {
  count_.bind(1, first);
  count_.bind(2, last);
  count_.step();
  const std::int64_t n = count_.column_int64(0);
  count_.reset();
  return n;
}

}  // namespace m2mlat::store::row_check
