// Clock samples to and from the events files' clock records.
#include "m2mlat/analysis/clock_records.hpp"

namespace m2mlat::analysis {

formats::ClockRecord to_clock_record(const store::ClockSample& s, const std::string& node) {
  return {node,           s.time.clock(),   s.time.ns(),    s.source,       s.offset_ns,
          s.max_error_ns, s.est_error_ns,   s.synchronised, s.detail_json};
}

store::ClockSample to_clock_sample(const formats::ClockRecord& r) {
  store::ClockSample s;
  s.time = core::TimePoint::from_ns(r.clock, r.time_ns);
  s.source = r.source;
  s.offset_ns = r.offset_ns;
  s.max_error_ns = r.max_error_ns;
  s.est_error_ns = r.est_error_ns;
  s.synchronised = r.synchronised;
  s.detail_json = r.detail_json;
  return s;
}

}  // namespace m2mlat::analysis
