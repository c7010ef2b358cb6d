#include "m2mlat/markers/command_rule.hpp"

#include <fmt/format.h>

#include <limits>
#include <nlohmann/json.hpp>

#include "m2mlat/core/error.hpp"
#include "m2mlat/core/number.hpp"
#include "m2mlat/core/time.hpp"

namespace m2mlat::markers {

namespace {

using json = nlohmann::json;

// Reads the top-level members a rule wants from a JSON object and stops as soon as it has them:
// a command's key is found without building the document.
class MemberReader : public nlohmann::json_sax<json> {
 public:
  MemberReader(const std::string* key_member, const std::string* ms_member)
      : key_member_(key_member), ms_member_(ms_member) {}

  std::optional<std::string> found_key;
  std::optional<std::int64_t> sender_ns;

  bool null() override { return scalar("null", nullptr); }
  bool boolean(bool value) override { return scalar(value ? "true" : "false", nullptr); }
  bool number_integer(number_integer_t value) override {
    std::optional<std::int64_t> ns;
    if (value <= kMaxMs && value >= -kMaxMs) ns = value * 1'000'000;
    return scalar(std::to_string(value), &ns);
  }
  bool number_unsigned(number_unsigned_t value) override {
    std::optional<std::int64_t> ns;
    if (value <= static_cast<number_unsigned_t>(kMaxMs)) ns = static_cast<std::int64_t>(value) * 1'000'000;
    return scalar(std::to_string(value), &ns);
  }
  bool number_float(number_float_t, const string_t& text) override {
    std::optional<std::int64_t> ns;
    if (std::int64_t parsed = 0; core::parse_ms(text, parsed)) ns = parsed;  // exact: no double
    return scalar(text, &ns);
  }
  bool string(string_t& value) override { return scalar(value, nullptr); }
  bool binary(binary_t&) override { return scalar({}, nullptr); }
  bool start_object(std::size_t) override {
    pending_ = Pending::none;
    return ++depth_ > 0;
  }
  bool key(string_t& name) override {
    pending_ = Pending::none;
    if (depth_ != 1) return true;
    if (key_member_ != nullptr && name == *key_member_ && !found_key) pending_ = Pending::key;
    if (ms_member_ != nullptr && name == *ms_member_ && !sender_ns)
      pending_ = pending_ == Pending::key ? Pending::both : Pending::ms;
    return true;
  }
  bool end_object() override {
    --depth_;
    return true;
  }
  bool start_array(std::size_t) override {
    if (depth_ == 0) return false;  // the payload is not an object
    pending_ = Pending::none;
    ++depth_;
    return true;
  }
  bool end_array() override {
    --depth_;
    return true;
  }
  bool parse_error(std::size_t, const std::string&, const nlohmann::detail::exception&) override { return false; }

 private:
  static constexpr std::int64_t kMaxMs = std::numeric_limits<std::int64_t>::max() / 1'000'000;
  enum class Pending : std::uint8_t { none, key, ms, both };

  bool scalar(const std::string& text, const std::optional<std::int64_t>* ns) {
    if (depth_ == 0) return false;  // a bare value: not an object
    if (pending_ == Pending::key || pending_ == Pending::both) found_key = text;
    if ((pending_ == Pending::ms || pending_ == Pending::both) && ns != nullptr) sender_ns = *ns;
    pending_ = Pending::none;
    // Stop reading once everything wanted is there.
    return !((key_member_ == nullptr || found_key) && (ms_member_ == nullptr || sender_ns));
  }

  const std::string* key_member_;
  const std::string* ms_member_;
  int depth_ = 0;
  Pending pending_ = Pending::none;
};

std::string hex(std::span<const std::uint8_t> bytes) {
  static constexpr char kDigits[] = "0123456789abcdef";
  std::string text(bytes.size() * 2, '0');
  for (std::size_t i = 0; i < bytes.size(); ++i) {
    text[2 * i] = kDigits[bytes[i] >> 4];
    text[2 * i + 1] = kDigits[bytes[i] & 0x0F];
  }
  return text;
}

std::uint64_t fnv1a(std::span<const std::uint8_t> bytes) {
  std::uint64_t hash = 0xcbf29ce484222325u;
  for (const auto byte : bytes) {
    hash ^= byte;
    hash *= 0x100000001b3u;
  }
  return hash;
}

}  // namespace

KeyRule parse_key_rule(std::string_view text) {
  const auto bad = [&](std::string_view why) {
    return core::Error(core::ErrorKind::usage,
                       fmt::format("key '{}': {} (json:NAME, bytes:OFFSET:LENGTH or hash)", text, why));
  };
  KeyRule rule;
  if (text == "hash") return rule;
  if (text.starts_with("json:")) {
    rule.kind = KeyRule::Kind::json;
    rule.member = std::string(text.substr(5));
    if (rule.member.empty()) throw bad("no member name");
    return rule;
  }
  if (text.starts_with("bytes:")) {
    const auto rest = text.substr(6);
    const auto colon = rest.find(':');
    if (colon == std::string_view::npos) throw bad("no length");
    std::int64_t offset = 0;
    std::int64_t length = 0;
    if (!core::parse_integer(rest.substr(0, colon), offset) || offset < 0) throw bad("the offset is not a byte count");
    if (!core::parse_integer(rest.substr(colon + 1), length) || length <= 0 || length > 4096)
      throw bad("the length is not 1 to 4096 bytes");
    rule.kind = KeyRule::Kind::bytes;
    rule.offset = static_cast<std::size_t>(offset);
    rule.length = static_cast<std::size_t>(length);
    return rule;
  }
  throw bad("unknown kind");
}

std::string to_string(const KeyRule& rule) {
  switch (rule.kind) {
    case KeyRule::Kind::json: return "json:" + rule.member;
    case KeyRule::Kind::bytes: return fmt::format("bytes:{}:{}", rule.offset, rule.length);
    case KeyRule::Kind::hash: return "hash";
  }
  return "?";
}

MessageKey message_key(const CommandRule& rule, std::span<const std::uint8_t> payload) {
  MessageKey result;
  const bool json_key = rule.key.kind == KeyRule::Kind::json;
  if (json_key || !rule.sender_ms.empty()) {
    MemberReader reader(json_key ? &rule.key.member : nullptr, rule.sender_ms.empty() ? nullptr : &rule.sender_ms);
    // Through char pointers: nlohmann's fastest input adapter (a byte iterator goes a slower way).
    const auto* text = reinterpret_cast<const char*>(payload.data());
    json::sax_parse(text, text + payload.size(), &reader, nlohmann::detail::input_format_t::json, false);
    if (json_key) result.key = std::move(reader.found_key);
    result.sender_ns = reader.sender_ns;
  }
  if (rule.key.kind == KeyRule::Kind::bytes && payload.size() >= rule.key.offset + rule.key.length)
    result.key = hex(payload.subspan(rule.key.offset, rule.key.length));
  if (rule.key.kind == KeyRule::Kind::hash) result.key = fmt::format("{:016x}", fnv1a(payload));
  return result;
}

}  // namespace m2mlat::markers
