// Field-by-field checks of sessions, events, clock samples and losses.
#include "m2mlat/store/validate.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <nlohmann/json.hpp>

#include "m2mlat/core/error.hpp"
#include "m2mlat/store/rate_block.hpp"
#include "m2mlat/store/rows.hpp"

namespace m2mlat::store::validate {

namespace {

[[noreturn]] void fail(const std::string& store_path, std::string_view what, std::string_view message) {
  core::throw_data_error({store_path, 0}, fmt::format("{}: {}", what, message));
}

void known_clock(const std::string& store_path, std::string_view what, std::string_view field,
                 core::TimePoint time) {
  if (!rows::is_known(time.clock()))
    fail(store_path, what,
         fmt::format("field '{}' has clock value {}, not a known clock", field,
                     static_cast<int>(time.clock())));
}

}  // namespace

void json(const std::string& store_path, std::string_view what, std::string_view field,
          const std::string& text) {
  if (nlohmann::json::accept(text)) return;
  try {
    // Parse only to get the parser's message (line, column, reason).
    const auto parsed = nlohmann::json::parse(text);
    (void)parsed;
  } catch (const nlohmann::json::exception& e) {  // parse_error, or out_of_range (1e999)
    // Drop the library's "[json.exception.parse_error.101] " prefix; keep line/column and reason.
    std::string_view reason = e.what();
    if (const auto close = reason.find("] "); reason.starts_with("[json.exception") && close != reason.npos)
      reason.remove_prefix(close + 2);
    fail(store_path, what, fmt::format("field '{}' is not valid JSON: {}", field, reason));
  }
  fail(store_path, what, fmt::format("field '{}' is not valid JSON", field));
}

void session(const std::string& store_path, const Session& s) {
  const std::string what = fmt::format("session '{}'", s.label);
  if (s.node.empty()) fail(store_path, what, "field 'node' is empty");
  if (!rows::is_known(s.role))
    fail(store_path, what,
         fmt::format("field 'role' has value {}, not a known role", static_cast<int>(s.role)));
  json(store_path, what, "config_json", s.config_json);
  known_clock(store_path, what, "start", s.start);
  if (s.end) {
    if (s.end->clock() != s.start.clock())
      fail(store_path, what,
           fmt::format("field 'end' is on clock {}, 'start' on {}", core::to_string(s.end->clock()),
                       core::to_string(s.start.clock())));
    if (*s.end < s.start) fail(store_path, what, "field 'end' is before 'start'");
  }
}

void event(const std::string& store_path, std::size_t index, const core::Event& e) {
  // On every event a recorder stores (twice: in the writer and in the append), so the message is
  // made only when a check fails.
  if (!e.channel.empty() && rows::is_known(e.edge) && rows::is_known(e.time.clock())) return;
  const std::string what = fmt::format("event {} of the batch", index);
  if (e.channel.empty()) fail(store_path, what, "field 'channel' is empty");
  if (!rows::is_known(e.edge))
    fail(store_path, what,
         fmt::format("field 'edge' has value {}, not a known edge", static_cast<int>(e.edge)));
  known_clock(store_path, what, "time", e.time);
}

void clock_sample(const std::string& store_path, std::size_t index, const ClockSample& s) {
  const std::string what = fmt::format("clock sample {} of the batch", index);
  known_clock(store_path, what, "time", s.time);
  const bool name_ok = !s.source.empty() && std::all_of(s.source.begin(), s.source.end(), [](char c) {
    return (c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') || c == '_';
  });
  if (!name_ok)
    fail(store_path, what,
         fmt::format("field 'source' is '{}' (expected lower-case letters, digits and '_', e.g. chrony)",
                     s.source));
  json(store_path, what, "detail_json", s.detail_json);
}

void loss(const std::string& store_path, std::size_t index, const Loss& l) {
  const std::string what = fmt::format("loss {} of the batch", index);
  known_clock(store_path, what, "detected_at", l.detected_at);
  if (l.count == 0) fail(store_path, what, "field 'count' is 0 (a loss has at least one missing event)");
  if (std::find(std::begin(kLossKinds), std::end(kLossKinds), l.kind) == std::end(kLossKinds))
    fail(store_path, what,
         fmt::format("field 'kind' is '{}' (expected one of {})", l.kind, fmt::join(kLossKinds, ", ")));
}

void rate_block(const std::string& store_path, std::size_t index, const RateBlock& b) {
  const std::string what = fmt::format("rate block {} of the batch", index);
  if (b.channel.empty()) fail(store_path, what, "field 'channel' is empty");
  if (!rows::is_known(b.clock))
    fail(store_path, what, fmt::format("field 'clock' has value {}, not a known clock", static_cast<int>(b.clock)));
  if (!std::isfinite(b.counts_per_deg_s) || b.counts_per_deg_s <= 0)
    fail(store_path, what, fmt::format("field 'counts_per_deg_s' is {} (expected > 0)", b.counts_per_deg_s));
  if (b.first_index > static_cast<std::uint64_t>(std::numeric_limits<std::int64_t>::max()))
    fail(store_path, what, fmt::format("field 'first_index' is {} (expected < 2^63)", b.first_index));
  if (b.samples.empty() || b.samples.size() > rate_block::kMaxSamples)
    fail(store_path, what,
         fmt::format("holds {} samples (expected 1 to {})", b.samples.size(), rate_block::kMaxSamples));
  for (std::size_t k = 0; k < b.samples.size(); ++k) {
    if (b.samples[k].bound_ns < 0)
      fail(store_path, what, fmt::format("sample {}: field 'bound_ns' is {} (expected >= 0)", k,
                                         b.samples[k].bound_ns));
    if (k > 0 && b.samples[k].time_ns < b.samples[k - 1].time_ns)
      fail(store_path, what, fmt::format("sample {}: field 'time_ns' {} is earlier than the sample before ({})",
                                         k, b.samples[k].time_ns, b.samples[k - 1].time_ns));
  }
}

void marker(const std::string& store_path, std::size_t index, const MarkerRecord& m) {
  const std::string what = fmt::format("marker {} of the batch", index);
  if (m.name.empty()) fail(store_path, what, "field 'name' is empty");
  known_clock(store_path, what, "time", m.time);
  const bool source_ok = !m.source.empty() && std::all_of(m.source.begin(), m.source.end(), [](char c) {
    return (c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') || c == '_';
  });
  if (!source_ok)
    fail(store_path, what,
         fmt::format("field 'source' is '{}' (expected lower-case letters, digits and '_', e.g. kernel)",
                     m.source));
  if (m.uncertainty_ns && *m.uncertainty_ns < 0)
    fail(store_path, what, fmt::format("field 'uncertainty_ns' is {} (expected >= 0)", *m.uncertainty_ns));
}

}  // namespace m2mlat::store::validate
