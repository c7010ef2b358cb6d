// Encoding and decoding of the agent API's JSON (wire.hpp). Decoding checks every field's presence,
// type and range and names the field in its error, so a coordinator can say which agent sent what.
#include "m2mlat/net/wire.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <iterator>
#include <limits>

#include "m2mlat/core/error.hpp"
#include "m2mlat/store/rate_block.hpp"

namespace m2mlat::net {

namespace {

using nlohmann::json;

[[noreturn]] void refuse(std::string_view where, std::string_view field, std::string_view problem) {
  throw core::Error(core::ErrorKind::data, fmt::format("{}: field '{}': {}", where, field, problem));
}

const json& member(const json& j, std::string_view where, std::string_view field) {
  if (!j.is_object()) refuse(where, field, "the value is not a JSON object");
  const auto it = j.find(std::string(field));
  if (it == j.end()) refuse(where, field, "missing");
  return *it;
}

std::int64_t get_int(const json& j, std::string_view where, std::string_view field,
                     std::int64_t min = std::numeric_limits<std::int64_t>::min()) {
  const auto& v = member(j, where, field);
  std::int64_t value = 0;
  if (v.is_number_unsigned()) {
    const auto u = v.get<std::uint64_t>();
    if (u > static_cast<std::uint64_t>(std::numeric_limits<std::int64_t>::max()))
      refuse(where, field, "out of range (int64)");
    value = static_cast<std::int64_t>(u);
  } else if (v.is_number_integer()) {
    value = v.get<std::int64_t>();
  } else {
    refuse(where, field, "not an integer");
  }
  if (value < min) refuse(where, field, fmt::format("{} is below the least allowed value {}", value, min));
  return value;
}

std::uint64_t get_uint(const json& j, std::string_view where, std::string_view field, std::uint64_t min = 0) {
  const auto& v = member(j, where, field);
  if (v.is_number_unsigned()) {
    const auto value = v.get<std::uint64_t>();
    if (value < min) refuse(where, field, fmt::format("{} is below the least allowed value {}", value, min));
    return value;
  }
  if (v.is_number_integer()) refuse(where, field, "negative");
  refuse(where, field, "not an integer");
}

std::optional<std::int64_t> get_optional_int(const json& j, std::string_view where, std::string_view field) {
  if (member(j, where, field).is_null()) return std::nullopt;
  return get_int(j, where, field);
}

std::string get_string(const json& j, std::string_view where, std::string_view field,
                       bool non_empty = false) {
  const auto& v = member(j, where, field);
  if (!v.is_string()) refuse(where, field, "not a string");
  auto text = v.get<std::string>();
  if (non_empty && text.empty()) refuse(where, field, "empty");
  return text;
}

bool get_bool(const json& j, std::string_view where, std::string_view field) {
  const auto& v = member(j, where, field);
  if (!v.is_boolean()) refuse(where, field, "not true or false");
  return v.get<bool>();
}

// A JSON object carried as text in the store (config_json, detail_json).
std::string get_object_text(const json& j, std::string_view where, std::string_view field) {
  const auto& v = member(j, where, field);
  if (!v.is_object()) refuse(where, field, "not a JSON object");
  return v.dump();
}

json object_from_text(const std::string& text) {
  auto parsed = json::parse(text, nullptr, false);
  return parsed.is_discarded() ? json::object() : parsed;
}

// Parses an enumerated name with `parse` (which throws core::Error(usage)), refusing other text.
template <typename Parse>
auto get_name(const json& j, std::string_view where, std::string_view field, Parse parse) {
  const auto text = get_string(j, where, field);
  try {
    const auto value = parse(text);
    if (to_string(value) != text) refuse(where, field, fmt::format("'{}' is not a canonical name", text));
    return value;
  } catch (const core::Error& e) {
    if (e.kind() == core::ErrorKind::data) throw;
    refuse(where, field, fmt::format("'{}': unknown", text));
  }
}

core::Clock get_clock(const json& j, std::string_view where) {
  return get_name(j, where, "clock", [](std::string_view t) { return core::parse_clock(t); });
}

json sample_fields(const store::ClockSample& s) {
  return {{"session", s.session_id},
          {"clock", core::to_string(s.time.clock())},
          {"t_ns", s.time.ns()},
          {"source", s.source},
          {"offset_ns", s.offset_ns},
          {"max_error_ns", s.max_error_ns},
          {"est_error_ns", s.est_error_ns},
          {"synchronised", s.synchronised},
          {"detail", object_from_text(s.detail_json)}};
}

store::ClockSample sample_from(const json& j, std::string_view where) {
  store::ClockSample s;
  s.session_id = get_int(j, where, "session", 1);
  s.time = core::TimePoint::from_ns(get_clock(j, where), get_int(j, where, "t_ns"));
  s.source = get_string(j, where, "source", true);
  if (!std::all_of(s.source.begin(), s.source.end(),
                   [](char c) { return (c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') || c == '_'; }))
    refuse(where, "source", fmt::format("'{}': only lower-case letters, digits and '_'", s.source));
  s.offset_ns = get_int(j, where, "offset_ns");
  s.max_error_ns = get_int(j, where, "max_error_ns", 0);
  s.est_error_ns = get_int(j, where, "est_error_ns", 0);
  s.synchronised = get_bool(j, where, "synchronised");
  s.detail_json = get_object_text(j, where, "detail");
  return s;
}

std::string nested(std::string_view where, std::string_view field) {
  return fmt::format("{} {}", where, field);
}

}  // namespace

json to_json(const store::Session& s) {
  return {{"id", s.id},
          {"label", s.label},
          {"scenario", s.scenario},
          {"node", s.node},
          {"role", core::to_string(s.role)},
          {"start_ns", s.start.ns()},
          {"end_ns", s.end ? json(s.end->ns()) : json(nullptr)},
          {"clock", core::to_string(s.start.clock())},
          {"config", object_from_text(s.config_json)},
          {"software_version", s.software_version}};
}

json to_json(const store::StoredEvent& e) {
  return {{"seq", e.seq},
          {"session", e.session_id},
          {"channel", e.event.channel},
          {"edge", core::to_string(e.event.edge)},
          {"clock", core::to_string(e.event.time.clock())},
          {"t_ns", e.event.time.ns()},
          {"seqno", e.event.seqno},
          {"line_seqno", e.event.line_seqno},
          {"flags", e.event.flags}};
}

void append_json(std::string& out, const store::StoredEvent& e) {
  // A channel name of printable ASCII without quote or backslash is its own JSON text; anything
  // else takes the JSON library's escaping (and its replacement of invalid UTF-8).
  const auto& channel = e.event.channel;
  const bool plain = std::all_of(channel.begin(), channel.end(),
                                 [](char c) { return c >= 0x20 && c <= 0x7e && c != '"' && c != '\\'; });
  const auto quoted = plain ? fmt::format("\"{}\"", channel)
                            : json(channel).dump(-1, ' ', false, json::error_handler_t::replace);
  // Keys in the order nlohmann::json (a std::map) writes them: alphabetical.
  fmt::format_to(std::back_inserter(out),
                 R"({{"channel":{},"clock":"{}","edge":"{}","flags":{},"line_seqno":{},"seq":{},"seqno":{},)"
                 R"("session":{},"t_ns":{}}})",
                 quoted, core::to_string(e.event.time.clock()), core::to_string(e.event.edge), e.event.flags,
                 e.event.line_seqno, e.seq, e.event.seqno, e.session_id, e.event.time.ns());
}

namespace {

// A reader of append_json's text: each step consumes what it expects or fails.
class CanonicalReader {
 public:
  explicit CanonicalReader(std::string_view text) : text_(text) {}
  bool literal(std::string_view expected) {
    if (text_.substr(pos_, expected.size()) != expected) return false;
    pos_ += expected.size();
    return true;
  }
  // Characters up to the next quote (consumed), all printable ASCII without a backslash.
  bool plain(std::string_view& out) {
    const auto end = text_.find('"', pos_);
    if (end == std::string_view::npos) return false;
    out = text_.substr(pos_, end - pos_);
    if (!std::all_of(out.begin(), out.end(), [](char c) { return c >= 0x20 && c <= 0x7e && c != '\\'; }))
      return false;
    pos_ = end + 1;
    return true;
  }
  template <typename Int>
  bool integer(Int& out) {
    const char* first = text_.data() + pos_;
    const char* last = text_.data() + text_.size();
    const char* digits = first != last && *first == '-' ? first + 1 : first;
    if (digits + 1 < last && *digits == '0' && digits[1] >= '0' && digits[1] <= '9') return false;
    const auto [end, ec] = std::from_chars(first, last, out);
    if (ec != std::errc()) return false;
    pos_ += static_cast<std::size_t>(end - first);
    return true;
  }
  bool at_end() const { return pos_ == text_.size(); }

 private:
  std::string_view text_;
  std::size_t pos_ = 0;
};

}  // namespace

std::optional<store::StoredEvent> parse_canonical_event(std::string_view line) {
  CanonicalReader r(line);
  store::StoredEvent e;
  std::string_view channel, clock, edge;
  std::int64_t t_ns = 0;
  if (!(r.literal(R"({"channel":")") && r.plain(channel) && r.literal(R"(,"clock":")") && r.plain(clock) &&
        r.literal(R"(,"edge":")") && r.plain(edge) && r.literal(R"(,"flags":)") && r.integer(e.event.flags) &&
        r.literal(R"(,"line_seqno":)") && r.integer(e.event.line_seqno) && r.literal(R"(,"seq":)") &&
        r.integer(e.seq) && r.literal(R"(,"seqno":)") && r.integer(e.event.seqno) &&
        r.literal(R"(,"session":)") && r.integer(e.session_id) && r.literal(R"(,"t_ns":)") &&
        r.integer(t_ns) && r.literal("}") && r.at_end()))
    return std::nullopt;
  if (channel.empty() || e.seq < 1 || e.session_id < 1) return std::nullopt;
  try {
    e.event.time = core::TimePoint::from_ns(core::parse_clock(clock), t_ns);
    e.event.edge = core::parse_edge(edge);
  } catch (const core::Error&) {
    return std::nullopt;
  }
  e.event.channel = channel;
  return e;
}

json to_json(const store::StoredClockSample& s) {
  auto j = sample_fields(s.sample);
  j["id"] = s.id;
  return j;
}

json to_json(const store::StoredLoss& l) {
  return {{"id", l.id},
          {"session", l.loss.session_id},
          {"channel", l.loss.channel},
          {"clock", core::to_string(l.loss.detected_at.clock())},
          {"t_ns", l.loss.detected_at.ns()},
          {"first_missing", l.loss.first_missing},
          {"count", l.loss.count},
          {"kind", l.loss.kind}};
}

json to_json(const store::StoredRateBlock& b) {
  json samples = json::array();
  for (const auto& x : b.block.samples) samples.push_back({x.time_ns, x.bound_ns, x.raw[0], x.raw[1], x.raw[2]});
  return {{"id", b.id},
          {"session", b.block.session_id},
          {"channel", b.block.channel},
          {"clock", core::to_string(b.block.clock)},
          {"counts_per_deg_s", b.block.counts_per_deg_s},
          {"first_index", b.block.first_index},
          {"samples", std::move(samples)}};
}

json to_json(const store::StoredMarker& m) {
  const auto& r = m.marker;
  return {{"id", m.id},
          {"session", r.session_id},
          {"name", r.name},
          {"clock", core::to_string(r.time.clock())},
          {"t_ns", r.time.ns()},
          {"source", r.source},
          {"uncertainty_ns", r.uncertainty_ns ? json(*r.uncertainty_ns) : json(nullptr)},
          {"key", r.key},
          {"sender_ns", r.sender_ns ? json(*r.sender_ns) : json(nullptr)},
          {"origin", r.origin}};
}

json mark_status_json(const MarkStatus& m) {
  json rejected = json::object();
  for (const auto& [reason, n] : m.rejected) rejected[reason] = n;
  return {{"address", m.address},
          {"stamps", m.stamps},
          {"stored", m.stored},
          {"rejected", rejected},
          {"last_rejection", m.last_rejection}};
}

json to_json(const Status& s) {
  json channels = json::array();
  for (const auto& c : s.channels)
    channels.push_back({{"name", c.name},
                        {"events", c.events},
                        {"suppressed", c.suppressed},
                        {"lost", c.lost},
                        {"last_ns", c.last_ns ? json(*c.last_ns) : json(nullptr)}});
  return {{"api", s.api},
          {"software_version", s.software_version},
          {"node", s.node},
          {"role", core::to_string(s.role)},
          {"store_id", s.store_id},
          {"session", s.session ? to_json(*s.session) : json(nullptr)},
          {"channels", channels},
          {"events", s.events},
          {"lost", s.lost},
          {"dropped", s.dropped},
          {"last_seq", s.last_seq},
          {"clock", s.clock ? sample_fields(*s.clock) : json(nullptr)},
          {"marks", s.marks ? mark_status_json(*s.marks) : json(nullptr)},
          {"started_ns", s.started_ns},
          {"now_ns", s.now_ns}};
}

store::Session session_from_json(const json& j, std::string_view where) {
  store::Session s;
  s.id = get_int(j, where, "id", 1);
  s.label = get_string(j, where, "label");
  s.scenario = get_string(j, where, "scenario");
  s.node = get_string(j, where, "node", true);
  s.role = get_name(j, where, "role", [](std::string_view t) { return core::parse_role(t); });
  const auto clock = get_clock(j, where);
  s.start = core::TimePoint::from_ns(clock, get_int(j, where, "start_ns"));
  if (const auto end = get_optional_int(j, where, "end_ns")) {
    if (*end < s.start.ns()) refuse(where, "end_ns", "before start_ns");
    s.end = core::TimePoint::from_ns(clock, *end);
  }
  s.config_json = get_object_text(j, where, "config");
  s.software_version = get_string(j, where, "software_version");
  return s;
}

store::StoredEvent event_from_json(const json& j, std::string_view where, const std::string& node,
                                   core::Role role) {
  (void)role;  // the role is the session's; an event carries none of its own
  store::StoredEvent e;
  e.seq = get_int(j, where, "seq", 1);
  e.session_id = get_int(j, where, "session", 1);
  e.event.node = node;
  e.event.channel = get_string(j, where, "channel", true);
  e.event.edge = get_name(j, where, "edge", [](std::string_view t) { return core::parse_edge(t); });
  e.event.time = core::TimePoint::from_ns(get_clock(j, where), get_int(j, where, "t_ns"));
  e.event.seqno = get_uint(j, where, "seqno");
  e.event.line_seqno = get_uint(j, where, "line_seqno");
  const auto flags = get_uint(j, where, "flags");
  if (flags > std::numeric_limits<std::uint32_t>::max()) refuse(where, "flags", "out of range (uint32)");
  e.event.flags = static_cast<std::uint32_t>(flags);
  return e;
}

store::StoredClockSample clock_sample_from_json(const json& j, std::string_view where) {
  store::StoredClockSample s;
  s.id = get_int(j, where, "id", 1);
  s.sample = sample_from(j, where);
  return s;
}

store::StoredLoss loss_from_json(const json& j, std::string_view where) {
  store::StoredLoss l;
  l.id = get_int(j, where, "id", 1);
  l.loss.session_id = get_int(j, where, "session", 1);
  l.loss.channel = get_string(j, where, "channel");
  l.loss.detected_at = core::TimePoint::from_ns(get_clock(j, where), get_int(j, where, "t_ns"));
  l.loss.first_missing = get_uint(j, where, "first_missing");
  l.loss.count = get_uint(j, where, "count", 1);
  l.loss.kind = get_string(j, where, "kind");
  if (std::find(std::begin(store::kLossKinds), std::end(store::kLossKinds), l.loss.kind) ==
      std::end(store::kLossKinds))
    refuse(where, "kind", fmt::format("'{}': unknown", l.loss.kind));
  return l;
}

store::StoredRateBlock rate_block_from_json(const json& j, std::string_view where) {
  store::StoredRateBlock b;
  b.id = get_int(j, where, "id", 1);
  b.block.session_id = get_int(j, where, "session", 1);
  b.block.channel = get_string(j, where, "channel", true);
  b.block.clock = get_clock(j, where);
  const auto& scale = member(j, where, "counts_per_deg_s");
  if (!scale.is_number() || !(scale.get<double>() > 0) || !std::isfinite(scale.get<double>()))
    refuse(where, "counts_per_deg_s", "not a positive number");
  b.block.counts_per_deg_s = scale.get<double>();
  b.block.first_index = get_uint(j, where, "first_index");
  const auto& samples = member(j, where, "samples");
  if (!samples.is_array() || samples.empty() || samples.size() > store::rate_block::kMaxSamples)
    refuse(where, "samples", fmt::format("not an array of 1 to {} samples", store::rate_block::kMaxSamples));
  b.block.samples.reserve(samples.size());
  for (std::size_t i = 0; i < samples.size(); ++i) {
    const auto& x = samples[i];
    const auto bad = [&](std::string_view problem) {
      refuse(where, fmt::format("samples[{}]", i), problem);
    };
    if (!x.is_array() || x.size() != 5 || !std::all_of(x.begin(), x.end(), [](const json& v) {
          return v.is_number_integer();
        }))
      bad("not [time_ns, bound_ns, x, y, z] of integers");
    const auto in = [&](const json& v, std::int64_t lo, std::int64_t hi) {
      if (v.is_number_unsigned() && v.get<std::uint64_t>() > static_cast<std::uint64_t>(hi)) return false;
      const auto n = v.get<std::int64_t>();
      return n >= lo && n <= hi;
    };
    constexpr auto i64 = std::numeric_limits<std::int64_t>::max();
    if (!in(x[0], std::numeric_limits<std::int64_t>::min(), i64)) bad("time_ns out of range (int64)");
    if (!in(x[1], 0, std::numeric_limits<std::int32_t>::max())) bad("bound_ns out of 0..2^31-1");
    for (int k = 2; k < 5; ++k)
      if (!in(x[k], -32768, 32767)) bad("a rate out of the int16 range");
    core::RateSample r;
    r.time_ns = x[0].get<std::int64_t>();
    r.bound_ns = static_cast<std::int32_t>(x[1].get<std::int64_t>());
    for (int k = 0; k < 3; ++k) r.raw[k] = static_cast<std::int16_t>(x[k + 2].get<std::int64_t>());
    if (i > 0 && r.time_ns < b.block.samples.back().time_ns) bad("stamped before the sample before it");
    b.block.samples.push_back(r);
  }
  return b;
}

store::StoredMarker marker_from_json(const json& j, std::string_view where) {
  store::StoredMarker m;
  m.id = get_int(j, where, "id", 1);
  auto& r = m.marker;
  r.session_id = get_int(j, where, "session", 1);
  r.name = get_string(j, where, "name", true);
  r.time = core::TimePoint::from_ns(get_clock(j, where), get_int(j, where, "t_ns"));
  r.source = get_string(j, where, "source", true);
  r.uncertainty_ns = get_optional_int(j, where, "uncertainty_ns");
  if (r.uncertainty_ns && *r.uncertainty_ns < 0) refuse(where, "uncertainty_ns", "negative");
  r.key = get_string(j, where, "key");
  r.sender_ns = get_optional_int(j, where, "sender_ns");
  r.origin = get_string(j, where, "origin");
  return m;
}

Status status_from_json(const json& j, std::string_view where) {
  Status s;
  s.api = get_string(j, where, "api");
  if (s.api != kApiName) refuse(where, "api", fmt::format("'{}': this build speaks {}", s.api, kApiName));
  s.software_version = get_string(j, where, "software_version");
  s.node = get_string(j, where, "node", true);
  s.role = get_name(j, where, "role", [](std::string_view t) { return core::parse_role(t); });
  s.store_id = get_string(j, where, "store_id");
  if (s.store_id.size() != 32 || !std::all_of(s.store_id.begin(), s.store_id.end(), [](char c) {
        return (c >= '0' && c <= '9') || (c >= 'a' && c <= 'f');
      }))
    refuse(where, "store_id", "not 32 lower-case hex digits");
  if (!member(j, where, "session").is_null())
    s.session = session_from_json(j.at("session"), nested(where, "session"));
  const auto& channels = member(j, where, "channels");
  if (!channels.is_array()) refuse(where, "channels", "not an array");
  for (std::size_t i = 0; i < channels.size(); ++i) {
    const auto at = fmt::format("{} channels[{}]", where, i);
    ChannelStatus c;
    c.name = get_string(channels[i], at, "name", true);
    c.events = get_uint(channels[i], at, "events");
    c.suppressed = get_uint(channels[i], at, "suppressed");
    c.lost = get_uint(channels[i], at, "lost");
    c.last_ns = get_optional_int(channels[i], at, "last_ns");
    s.channels.push_back(std::move(c));
  }
  s.events = get_uint(j, where, "events");
  s.lost = get_uint(j, where, "lost");
  s.dropped = get_uint(j, where, "dropped");
  s.last_seq = get_int(j, where, "last_seq", 0);
  if (!member(j, where, "clock").is_null()) s.clock = sample_from(j.at("clock"), nested(where, "clock"));
  s.started_ns = get_int(j, where, "started_ns");
  s.now_ns = get_int(j, where, "now_ns");
  // Optional: agents older than the marker port send no "marks" (a coordinator reads both).
  if (const auto it = j.find("marks"); it != j.end() && !it->is_null()) {
    const auto& m = *it;
    if (!m.is_object()) refuse(where, "marks", "not an object or null");
    const auto at = nested(where, "marks");
    MarkStatus marks;
    marks.address = get_string(m, at, "address");
    marks.stamps = get_string(m, at, "stamps");
    marks.stored = get_uint(m, at, "stored");
    const auto& rejected = member(m, at, "rejected");
    if (!rejected.is_object()) refuse(at, "rejected", "not an object");
    for (const auto& [reason, n] : rejected.items()) {
      if (!n.is_number_unsigned()) refuse(at, "rejected", fmt::format("'{}' is not a count", reason));
      marks.rejected.emplace_back(reason, n.get<std::uint64_t>());
    }
    marks.last_rejection = get_string(m, at, "last_rejection");
    s.marks = std::move(marks);
  }
  return s;
}

std::string error_body(int status, std::string_view message) {
  // The message may quote request bytes: replace what is not UTF-8 rather than fail.
  return json{{"error", {{"status", status}, {"message", std::string(message)}}}}.dump(
      -1, ' ', false, json::error_handler_t::replace);
}

}  // namespace m2mlat::net
