// Clock steps to and from "step" clock samples.
#include "m2mlat/store/clock_step.hpp"

#include <algorithm>
#include <nlohmann/json.hpp>

namespace m2mlat::store {

ClockSample step_clock_sample(const ClockStep& step, core::Clock clock) {
  ClockSample sample;
  sample.time = core::TimePoint::from_ns(clock, step.at_ns);
  sample.source = std::string(kStepSource);
  sample.offset_ns = step.size_ns.value_or(0);
  sample.max_error_ns = step.size_ns ? step.size_max_ns : kUnknownSize;
  sample.est_error_ns = step.size_ns ? step.size_est_ns : kUnknownSize;
  sample.synchronised = false;
  nlohmann::json detail{{"to_ns", step.at_ns},
                        {"earliest_ns", step.earliest_ns},
                        {"size_known", step.size_ns.has_value()},
                        {"origin", step.origin}};
  if (step.size_ns) {
    detail["step_ns"] = *step.size_ns;
    detail["from_ns"] = step.at_ns - *step.size_ns;
  }
  sample.detail_json = detail.dump();
  return sample;
}

std::optional<ClockStep> clock_step_of(const ClockSample& sample) {
  if (sample.source != kStepSource) return std::nullopt;
  const auto detail = nlohmann::json::parse(sample.detail_json, nullptr, false);
  if (!detail.is_object()) return std::nullopt;
  const auto integer = [&](const char* key) -> std::optional<std::int64_t> {
    const auto it = detail.find(key);
    if (it == detail.end() || !it->is_number_integer()) return std::nullopt;
    return it->get<std::int64_t>();
  };
  ClockStep step;
  step.at_ns = sample.time.ns();
  step.earliest_ns = integer("earliest_ns").value_or(step.at_ns);
  if (step.earliest_ns > step.at_ns) step.earliest_ns = step.at_ns;
  const auto known = detail.find("size_known");
  const bool size_known = known == detail.end() ? integer("step_ns").has_value()
                                                : (known->is_boolean() && known->get<bool>());
  if (size_known) {
    step.size_ns = integer("step_ns").value_or(sample.offset_ns);
    if (known == detail.end()) {
      // An older monitor record: its error fields held |step|; the size is known to within what
      // the rates explained. Standard uncertainty: half that bound.
      const std::int64_t magnitude = *step.size_ns < 0 ? -*step.size_ns : *step.size_ns;
      step.size_max_ns = std::max<std::int64_t>(0, magnitude - integer("unexplained_ns").value_or(magnitude));
      step.size_est_ns = (step.size_max_ns + 1) / 2;
    } else {
      step.size_max_ns = sample.max_error_ns < 0 ? kUnknownSize : sample.max_error_ns;
      step.size_est_ns = sample.est_error_ns < 0 ? kUnknownSize : sample.est_error_ns;
    }
  }
  const auto origin = detail.find("origin");
  step.origin = origin != detail.end() && origin->is_string() ? origin->get<std::string>() : "monitor";
  return step;
}

ClockSample unknown_clock_sample(const UnknownClock& lines, core::Clock clock) {
  ClockSample sample;
  sample.time = core::TimePoint::from_ns(clock, lines.from_ns);
  sample.source = std::string(kUnknownClockSource);
  sample.synchronised = false;
  sample.detail_json = nlohmann::json{{"to_ns", lines.to_ns}, {"lines", lines.lines}, {"reason", lines.reason}}.dump();
  return sample;
}

std::optional<UnknownClock> unknown_clock_of(const ClockSample& sample) {
  if (sample.source != kUnknownClockSource) return std::nullopt;
  const auto detail = nlohmann::json::parse(sample.detail_json, nullptr, false);
  if (!detail.is_object()) return std::nullopt;
  const auto to = detail.find("to_ns");
  const auto lines = detail.find("lines");
  const auto reason = detail.find("reason");
  if (to == detail.end() || !to->is_number_integer() || reason == detail.end() || !reason->is_string())
    return std::nullopt;
  UnknownClock out;
  out.from_ns = sample.time.ns();
  out.to_ns = std::max(out.from_ns, to->get<std::int64_t>());
  out.lines = lines != detail.end() && lines->is_number_integer() ? lines->get<std::int64_t>() : 1;
  out.reason = reason->get<std::string>();
  return out;
}

}  // namespace m2mlat::store
