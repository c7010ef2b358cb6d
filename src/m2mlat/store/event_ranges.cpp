// Cutting the events into ranges by their spans, and checking each range once.
#include "m2mlat/store/event_ranges.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <limits>

namespace m2mlat::store::event_ranges {

Checked::Checked(sqlite::Database& db)
    : events_(db),
      new_spans_(db, "SELECT id, first_seq, last_seq, count FROM event_spans WHERE id > ?1 ORDER BY id") {}

void Checked::refresh() {
  // The new spans as ranges of their own, then merged with those they overlap. Spans are written
  // with increasing seqs, so new ones lie after the old (a migrated version-4 store's, grouped by
  // bucket, and a file edited by another tool are sorted here).
  const std::size_t old_size = ranges_.size();
  new_spans_.bind(1, last_span_id_);
  while (new_spans_.step()) {
    last_span_id_ = new_spans_.column_int64(0);
    ranges_.push_back(
        {new_spans_.column_int64(1), new_spans_.column_int64(2), new_spans_.column_int64(3), false});
  }
  new_spans_.reset();
  const auto by_first = [](const Range& a, const Range& b) { return a.first < b.first; };
  std::size_t start = old_size == 0 ? 0 : old_size - 1;  // the first range that may change
  if (!std::is_sorted(ranges_.begin() + static_cast<std::ptrdiff_t>(start), ranges_.end(), by_first)) {
    std::sort(ranges_.begin(), ranges_.end(), by_first);
    start = 0;
  }
  std::size_t out = start;
  for (std::size_t i = start + 1; i < ranges_.size(); ++i) {
    Range& merged = ranges_[out];
    if (ranges_[i].first <= merged.last) {  // overlapping: one range, to be checked (again)
      merged.last = std::max(merged.last, ranges_[i].last);
      merged.spanned += ranges_[i].spanned;
      merged.checked = false;
    } else {
      ranges_[++out] = ranges_[i];
    }
  }
  if (!ranges_.empty()) ranges_.resize(out + 1);
  holes_checked_ = std::min(holes_checked_, start);
  for (; holes_checked_ < ranges_.size(); ++holes_checked_) check_hole(holes_checked_);
  check_hole(0);  // before the first range and after the last: where an INSERT without a seq goes
  check_hole(ranges_.size());
}

void Checked::check(std::span<const std::int64_t> seqs) {
  for (const std::int64_t seq : seqs) {
    auto after = std::upper_bound(ranges_.begin(), ranges_.end(), seq,
                                  [](std::int64_t s, const Range& r) { return s < r.first; });
    if (after == ranges_.begin()) continue;  // before every range: no span of the read's snapshot
    Range& range = *std::prev(after);
    if (!range.checked && seq <= range.last) check(range);
  }
}

void Checked::check_all() {
  for (Range& range : ranges_) check(range);
}

void Checked::check(Range& range) {
  events_.check(range.first, range.last, range.spanned);
  range.checked = true;
}

void Checked::check_hole(std::size_t i) {
  constexpr auto kMin = std::numeric_limits<std::int64_t>::min(),
                 kMax = std::numeric_limits<std::int64_t>::max();
  const Range* before = i > 0 ? &ranges_[i - 1] : nullptr;
  const Range* after = i < ranges_.size() ? &ranges_[i] : nullptr;
  if (before && after && after->first - before->last <= 1) return;  // adjacent: no seq between them
  const auto seq = events_.first_between(before ? before->last : kMin, after ? after->first : kMax);
  if (!seq) return;
  // Named as a count over the ranges around the hole, which the event would have belonged to.
  events_.refuse_count(before ? before->first : *seq, after ? after->last : *seq,
                       (before ? before->spanned : 0) + (after ? after->spanned : 0),
                       fmt::format(" (seq {} lies in no span)", *seq));
}

}  // namespace m2mlat::store::event_ranges
