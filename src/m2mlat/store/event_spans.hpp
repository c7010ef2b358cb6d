// Event spans (schema version 5): the summary, per committed batch, that replaces the events table's
// per-row secondary indexes (docs/store.md "Event spans").
//
// A span is one (session, channel, clock) group of the events one transaction inserted: the seq
// range its rows lie in (first_seq..last_seq; rows of other groups of the same batch may lie in
// between), their earliest and latest t_ns (ns on the clock) and their number. It is written in the
// transaction that inserts the rows, so an open session, or one whose recorder was killed, is as
// readable as an ended one. Readers select spans by time or by session through the spans' own small
// indexes and read the events of each span by rowid range. Every event lies in exactly one span whose
// session, channel and clock are its own, which is what keeps a read free of duplicates.
//
// Why: maintaining events_by_time and events_by_session per row cost about 60 % of SQLite's work per
// stored event (a recorder's 512-event batches, measured with callgrind, docs/capture.md); a span
// costs one row per channel per batch.
#pragma once

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "m2mlat/core/time.hpp"
#include "m2mlat/store/sqlite.hpp"

namespace m2mlat::store::event_spans {

inline constexpr std::string_view kInsertSpan =
    "INSERT INTO event_spans (session_id, channel, clock, first_seq, last_seq, first_ns, last_ns, count) "
    "VALUES (?1, ?2, ?3, ?4, ?5, ?6, ?7, ?8)";

// Gathers the spans of one transaction's inserted events, then writes them.
class SpanBuilder {
 public:
  // One inserted event row (seq is its rowid; t_ns on `clock`).
  void add(std::int64_t seq, std::int64_t session_id, std::string_view channel, core::Clock clock,
           std::int64_t t_ns);
  // Inserts one row per group with `insert` (a statement of kInsertSpan) and forgets them.
  void write(sqlite::Statement& insert);

 private:
  struct Span {
    std::int64_t session_id;
    std::string channel;
    std::int64_t clock;
    std::int64_t first_seq, last_seq;
    std::int64_t first_ns, last_ns;
    std::int64_t count;
  };
  // A batch holds a handful of groups (a recorder's: one per line): a linear search of a short
  // vector, the last match tried first, beats any map.
  std::vector<Span> spans_;
  std::size_t last_ = 0;
};

}  // namespace m2mlat::store::event_spans
