// Grouping one transaction's events into spans.
#include "m2mlat/store/event_spans.hpp"

#include <algorithm>

namespace m2mlat::store::event_spans {

void SpanBuilder::add(std::int64_t seq, std::int64_t session_id, std::string_view channel, core::Clock clock,
                      std::int64_t t_ns) {
  const auto clock_column = static_cast<std::int64_t>(clock);
  const auto matches = [&](const Span& s) {
    return s.session_id == session_id && s.clock == clock_column && s.channel == channel;
  };
  Span* span = nullptr;
  if (last_ < spans_.size() && matches(spans_[last_])) {
    span = &spans_[last_];
  } else {
    const auto found = std::find_if(spans_.begin(), spans_.end(), matches);
    if (found == spans_.end()) {
      spans_.push_back(Span{session_id, std::string(channel), clock_column, seq, seq, t_ns, t_ns, 0});
      last_ = spans_.size() - 1;
    } else {
      last_ = static_cast<std::size_t>(found - spans_.begin());
    }
    span = &spans_[last_];
  }
  span->first_seq = std::min(span->first_seq, seq);
  span->last_seq = std::max(span->last_seq, seq);
  span->first_ns = std::min(span->first_ns, t_ns);
  span->last_ns = std::max(span->last_ns, t_ns);
  ++span->count;
}

void SpanBuilder::write(sqlite::Statement& insert) {
  for (const Span& span : spans_) {
    insert.bind(1, span.session_id);
    insert.bind(2, span.channel);
    insert.bind(3, span.clock);
    insert.bind(4, span.first_seq);
    insert.bind(5, span.last_seq);
    insert.bind(6, span.first_ns);
    insert.bind(7, span.last_ns);
    insert.bind(8, span.count);
    insert.step();
    insert.reset();
  }
  spans_.clear();
  last_ = 0;
}

}  // namespace m2mlat::store::event_spans
