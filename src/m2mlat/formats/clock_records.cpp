// Clock records of the events files as JSON objects.
#include "m2mlat/formats/clock_records.hpp"

#include <nlohmann/json.hpp>

#include "m2mlat/formats/event_fields.hpp"
#include "m2mlat/formats/json_fields.hpp"

namespace m2mlat::formats {

std::string clock_record_json(const ClockRecord& r) {
  auto detail = nlohmann::json::parse(r.detail_json, nullptr, false);
  if (!detail.is_object()) detail = nlohmann::json::object();
  nlohmann::json j{{"node", r.node},
                   {"clock", std::string(core::to_string(r.clock))},
                   {"time_ns", r.time_ns},
                   {"source", r.source},
                   {"offset_ns", r.offset_ns},
                   {"max_error_ns", r.max_error_ns},
                   {"est_error_ns", r.est_error_ns},
                   {"synchronised", r.synchronised},
                   {"detail", std::move(detail)}};
  return j.dump();
}

ClockRecord parse_clock_record(std::string_view json, std::string_view file, long line) {
  const JsonLine parsed(json, file, line);
  ClockRecord r;
  bool has[4] = {false, false, false, false};  // node, time_ns, source, synchronised
  for (const auto& [key, value] : parsed.object().items()) {
    if (key == "node") {
      r.node = parsed.text(key, value);
      has[0] = true;
    } else if (key == "clock") {
      if (!clock_from_name(parsed.text(key, value), r.clock))
        parsed.fail(key, value, "is not a clock (realtime, monotonic, boottime, simulated)");
    } else if (key == "time_ns") {
      r.time_ns = parsed.int64(key, value);
      has[1] = true;
    } else if (key == "source") {
      r.source = parsed.text(key, value);
      has[2] = true;
    } else if (key == "offset_ns") {
      r.offset_ns = parsed.int64(key, value);
    } else if (key == "max_error_ns") {
      r.max_error_ns = parsed.int64(key, value);
    } else if (key == "est_error_ns") {
      r.est_error_ns = parsed.int64(key, value);
    } else if (key == "synchronised") {
      if (!value.is_boolean()) parsed.fail(key, value, "is not true or false");
      r.synchronised = value.get<bool>();
      has[3] = true;
    } else if (key == "detail") {
      if (!value.is_object()) parsed.fail(key, value, "is not an object");
      r.detail_json = value.dump();
    } else {
      parsed.unknown_member(key);
    }
  }
  if (!has[0]) parsed.missing("node");
  if (!has[1]) parsed.missing("time_ns");
  if (!has[2]) parsed.missing("source");
  if (!has[3]) parsed.missing("synchronised");
  return r;
}

}  // namespace m2mlat::formats
