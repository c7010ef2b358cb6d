// Finding rows that break the schema's rules in a store file written or edited by another tool
// (SQLite lets a connection switch CHECK constraints off, and foreign keys are off by default).
//
// The reads of the store select rows by clock, edge, channel and session, so such a row would be
// left out of an analysis or a merge without a word; the checks here find the first one instead and
// name the file, the table, the row and the field. Every table but events is small beside it and is
// scanned whole (check_tables); the events are checked by seq range (EventCheck), so that a read pays
// for the ranges it reads, not for the whole store (store/event_ranges.hpp keeps which ranges were
// checked). The agent's resume-by-seq read needs neither: it reads every row and refuses a bad one as
// it decodes it.
#pragma once

#include <cstdint>
#include <optional>
#include <string_view>

#include "m2mlat/store/sqlite.hpp"

namespace m2mlat::store::row_check {

// Throws core::Error(data) "<file>: table 'losses' row id 4: field 'count' holds 0 (expected a
// non-zero integer): ..." for the first row breaking a rule in any table but events; returns if
// there is none. One scan of each table.
void check_tables(sqlite::Database& db);

// The events' rules within seq ranges, with the statements prepared once (a read may check
// thousands of ranges).
class EventCheck {
 public:
  explicit EventCheck(sqlite::Database& db);

  // Throws core::Error(data) "<file>: table 'events' row seq 42: field 'edge' holds 2 (expected 0 or
  // 1): ..." for the first event with first <= seq <= last breaking a rule, and "table 'events' holds
  // 6 rows, its spans (table 'event_spans') count 5, from seq 1 to 6" if they are not `spanned` in
  // number (an event inserted by another tool without a span, or deleted under one).
  void check(std::int64_t first, std::int64_t last, std::int64_t spanned);
  // The smallest seq above `after` and below `before`, if an event has one. A range query on the
  // rowid: one b-tree descent, whatever the table's size.
  std::optional<std::int64_t> first_between(std::int64_t after, std::int64_t before);
  // Throws the error of check() for first..last, `why` appended (an event found outside every span).
  [[noreturn]] void refuse_count(std::int64_t first, std::int64_t last, std::int64_t spanned,
                                 std::string_view why);

 private:
  std::int64_t count(std::int64_t first, std::int64_t last);

  sqlite::Database& db_;
  sqlite::Statement rules_;  // ?1, ?2: the seq range
  sqlite::Statement count_;
  sqlite::Statement between_;
};

}  // namespace m2mlat::store::row_check
