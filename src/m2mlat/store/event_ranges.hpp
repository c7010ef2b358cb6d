// Which events an open Store has checked (docs/store.md "Checking rows by range"): the events table
// cut into seq ranges by its spans, each checked once, when a read first needs it.
//
// A range is the union of spans whose seq ranges overlap (one committed batch, as a rule: its
// groups' spans interleave), with the sum of their counts. A read checks the ranges of the spans it
// selects (row_check::EventCheck: each event's rules and the range's number of events), so its first
// read of a big store costs time in proportion to what it reads. An event outside every range (one
// inserted by another tool without a span) would be seen by no read at all: every refresh looks for
// one before the first range and after the last, and in the holes between ranges it has not looked
// at yet (each one rowid range query), and refuses every read while one is there.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "m2mlat/store/row_check.hpp"
#include "m2mlat/store/sqlite.hpp"

namespace m2mlat::store::event_ranges {

class Checked {
 public:
  // Nothing is read before refresh().
  explicit Checked(sqlite::Database& db);

  // Takes in the spans written since the last refresh (all of them the first time: one row a span,
  // the events untouched) and looks for events outside every range (the holes not looked at
  // before, and always before the first range and after the last, where another tool's INSERT
  // puts them). Throws core::Error(data) naming the store and the rows' numbers.
  void refresh();
  // Checks the ranges that hold these seqs (a read's spans' first seqs) and were not checked yet.
  void check(std::span<const std::int64_t> seqs);
  // Checks every range, also those checked before (the whole store: what Store::check_rows does).
  void check_all();

 private:
  struct Range {
    std::int64_t first, last;  // seqs, first <= last
    std::int64_t spanned;      // the sum of its spans' counts
    bool checked;
  };
  void check(Range& range);
  // Throws if an event lies strictly between ranges_[i - 1] and ranges_[i] (i = 0: before the first
  // range; i = size: after the last).
  void check_hole(std::size_t i);

  row_check::EventCheck events_;
  sqlite::Statement new_spans_;  // ?1: the largest span id taken in
  std::vector<Range> ranges_;    // by seq, disjoint
  std::int64_t last_span_id_ = 0;
  std::size_t holes_checked_ = 0;  // the holes before ranges_[0 .. holes_checked_) were checked
};

}  // namespace m2mlat::store::event_ranges
