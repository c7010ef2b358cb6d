// Parsing and writing of `m2mlat-mark/1` datagrams (mark_datagram.hpp). Strict: a datagram that is
// not exactly the format is refused with a reason, never half read, so that nothing stored is a guess.
#include "m2mlat/markers/mark_datagram.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <vector>

#include "m2mlat/core/error.hpp"
#include "m2mlat/core/number.hpp"
#include "m2mlat/core/printable.hpp"

namespace m2mlat::markers {

namespace {

MarkParse refuse_mark(std::string_view reason, std::string detail) {
  MarkParse out;
  out.reason = reason;
  out.detail = std::move(detail);
  return out;
}

bool is_name_char(char c) {
  return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '_' || c == '.' ||
         c == ':' || c == '/' || c == '-';
}

}  // namespace

bool valid_mark_name(std::string_view name) {
  return !name.empty() && name.size() <= kMarkMaxName && std::all_of(name.begin(), name.end(), is_name_char);
}

bool valid_mark_key(std::string_view key) {
  return !key.empty() && key.size() <= kMarkMaxKey &&
         std::all_of(key.begin(), key.end(), [](char c) { return c > ' ' && c <= '~'; });
}

MarkParse parse_mark(std::string_view text) {
  if (text.size() > kMarkMaxBytes)
    return refuse_mark("size", fmt::format("{} bytes (at most {})", text.size(), kMarkMaxBytes));
  if (text.ends_with('\n')) text.remove_suffix(1);
  if (text.ends_with('\r')) text.remove_suffix(1);
  std::vector<std::string_view> words;
  for (std::size_t at = 0; at < text.size();) {
    if (text[at] == ' ') {
      ++at;
      continue;
    }
    const auto end = std::min(text.find(' ', at), text.size());
    words.push_back(text.substr(at, end - at));
    at = end;
  }
  if (words.empty() || words[0] != kMarkFormat)
    return refuse_mark("format", fmt::format("does not start with '{} ': '{}'", kMarkFormat,
                                             core::printable(text.substr(0, 40))));
  if (words.size() < 2) return refuse_mark("name", "no NAME");
  MarkDatagram mark;
  if (!valid_mark_name(words[1]))
    return refuse_mark("name", fmt::format("'{}' is not 1 to {} letters, digits or _ . : / -",
                                           core::printable(words[1].substr(0, 80)), kMarkMaxName));
  mark.name = words[1];
  bool have_key = false;
  for (std::size_t i = 2; i < words.size(); ++i) {
    const std::string_view word = words[i];
    const auto eq = word.find('=');
    const std::string_view field = word.substr(0, eq);
    const std::string_view value = eq == std::string_view::npos ? std::string_view() : word.substr(eq + 1);
    if (eq == std::string_view::npos || (field != "key" && field != "t"))
      return refuse_mark("field", fmt::format("'{}' is not key=KEY or t=NS", core::printable(word.substr(0, 80))));
    if (field == "key") {
      if (have_key) return refuse_mark("field", "key= given twice");
      if (!valid_mark_key(value))
        return refuse_mark("key", fmt::format("'{}' is not 1 to {} printable characters",
                                              core::printable(value.substr(0, 80)), kMarkMaxKey));
      mark.key = value;
      have_key = true;
    } else {
      if (mark.sender_ns) return refuse_mark("field", "t= given twice");
      const bool digits = !value.empty() && value.size() <= 19 &&
                          std::all_of(value.begin(), value.end(), [](char c) { return c >= '0' && c <= '9'; });
      std::int64_t ns = 0;
      if (!digits || !core::parse_integer(value, ns) || ns <= 0)
        return refuse_mark("time", fmt::format("t='{}' is not CLOCK_REALTIME in ns (a positive integer)",
                                               core::printable(value.substr(0, 40))));
      mark.sender_ns = ns;
    }
  }
  MarkParse out;
  out.mark = std::move(mark);
  return out;
}

std::string format_mark(const MarkDatagram& mark) {
  if (!valid_mark_name(mark.name))
    throw core::Error(core::ErrorKind::usage,
                      fmt::format("marker name '{}': expected 1 to {} letters, digits or _ . : / -",
                                  core::printable(mark.name), kMarkMaxName));
  std::string out = fmt::format("{} {}", kMarkFormat, mark.name);
  if (!mark.key.empty()) {
    if (!valid_mark_key(mark.key))
      throw core::Error(core::ErrorKind::usage,
                        fmt::format("marker key '{}': expected 1 to {} printable characters without spaces",
                                    core::printable(mark.key), kMarkMaxKey));
    out += fmt::format(" key={}", mark.key);
  }
  if (mark.sender_ns) out += fmt::format(" t={}", *mark.sender_ns);
  out += '\n';
  return out;
}

}  // namespace m2mlat::markers
