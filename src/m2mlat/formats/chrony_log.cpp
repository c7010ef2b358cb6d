// chronyd's step messages from a log (messages and rules in chrony_log.hpp).
#include "m2mlat/formats/chrony_log.hpp"

#include <fmt/format.h>

#include <nlohmann/json.hpp>

#include <charconv>
#include <chrono>
#include <cstdint>
#include <cstdlib>

#include "m2mlat/formats/fields.hpp"
#include "m2mlat/formats/input_text.hpp"

namespace m2mlat::formats {

namespace {

constexpr std::string_view kStepped = "System clock was stepped by ";
constexpr std::string_view kWrong = "System clock wrong by ";
constexpr std::string_view kForward = "Forward time jump detected!";
constexpr std::string_view kBackward = "Backward time jump detected!";
constexpr std::string_view kSeconds = " seconds";
constexpr std::string_view kInitial = "System's initial offset : ";
constexpr std::string_view kLeap = "System clock was stepped for leap second";
constexpr std::string_view kFailed = "Could not step system clock";

bool digits(std::string_view text, std::size_t pos, std::size_t count, int& out) {
  if (pos + count > text.size()) return false;
  out = 0;
  for (std::size_t i = pos; i < pos + count; ++i) {
    if (text[i] < '0' || text[i] > '9') return false;
    out = out * 10 + (text[i] - '0');
  }
  return true;
}

// The decimal seconds after `prefix` up to " seconds".
std::string_view seconds_after(std::string_view line, std::size_t at, std::string_view prefix) {
  const std::size_t from = at + prefix.size();
  const std::size_t end = line.find(kSeconds, from);
  return end == std::string_view::npos ? std::string_view{} : line.substr(from, end - from);
}

// A line of `journalctl -o json`: its MESSAGE and its __REALTIME_TIMESTAMP (us since 1970, a string).
struct JournalEntry {
  std::string message;
  LogStamp stamp;
};
std::optional<JournalEntry> journal_entry(std::string_view line) {
  if (line.empty() || line.front() != '{') return std::nullopt;
  const auto doc = nlohmann::json::parse(line, nullptr, false);
  if (!doc.is_object() || !doc.contains("MESSAGE") || !doc["MESSAGE"].is_string()) return std::nullopt;
  JournalEntry entry{doc["MESSAGE"].get<std::string>(), {}};
  const auto at = doc.find("__REALTIME_TIMESTAMP");
  if (at != doc.end() && at->is_string()) {
    const auto text = at->get<std::string>();
    std::int64_t us = 0;
    const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), us);
    if (ec == std::errc{} && end == text.data() + text.size() && us >= 0 && us < INT64_MAX / 1000)
      entry.stamp = LogStamp{us * 1000, 1000, 0};
  }
  return entry;
}

}  // namespace

std::optional<LogStamp> parse_log_stamp(std::string_view text) {
  int year = 0, month = 0, day = 0, hour = 0, minute = 0, second = 0;
  if (!digits(text, 0, 4, year) || text.size() < 19 || text[4] != '-' || !digits(text, 5, 2, month) ||
      text[7] != '-' || !digits(text, 8, 2, day) || (text[10] != 'T' && text[10] != ' ') ||
      !digits(text, 11, 2, hour) || text[13] != ':' || !digits(text, 14, 2, minute) || text[16] != ':' ||
      !digits(text, 17, 2, second))
    return std::nullopt;
  using namespace std::chrono;
  const year_month_day date{std::chrono::year{year}, std::chrono::month{static_cast<unsigned>(month)},
                            std::chrono::day{static_cast<unsigned>(day)}};
  if (!date.ok() || hour > 23 || minute > 59 || second > 60) return std::nullopt;
  LogStamp stamp;
  std::size_t pos = 19;
  std::int64_t fraction = 0;
  stamp.resolution_ns = 1'000'000'000;
  if (pos < text.size() && (text[pos] == '.' || text[pos] == ',')) {
    std::size_t n = 0;
    ++pos;
    while (pos < text.size() && text[pos] >= '0' && text[pos] <= '9') {
      if (n < 9) {
        fraction = fraction * 10 + (text[pos] - '0');
        stamp.resolution_ns /= 10;
      }
      ++n;
      ++pos;
    }
    if (n == 0) return std::nullopt;
    for (std::size_t k = n; k < 9; ++k) fraction *= 10;
  }
  std::int64_t offset_s = 0;  // local - UTC
  if (pos < text.size() && text[pos] == 'Z') {
    ++pos;
  } else if (pos < text.size() && (text[pos] == '+' || text[pos] == '-')) {
    const int sign = text[pos] == '-' ? -1 : 1;
    int oh = 0, om = 0;
    if (!digits(text, pos + 1, 2, oh)) return std::nullopt;
    std::size_t m = pos + 3;
    if (m < text.size() && text[m] == ':') ++m;
    if (!digits(text, m, 2, om)) return std::nullopt;
    offset_s = sign * (oh * 3600 + om * 60);
    pos = m + 2;
  } else {
    return std::nullopt;  // a local time without its zone cannot be placed
  }
  const std::int64_t days = sys_days(date).time_since_epoch().count();
  const std::int64_t seconds = days * 86400 + hour * 3600 + minute * 60 + second - offset_s;
  stamp.ns = seconds * 1'000'000'000 + fraction;
  stamp.length = pos;
  return stamp;
}

ChronyLogImport import_chrony_log(std::string_view text, std::string_view name) {
  ChronyLogImport result;
  LineReader reader(text);
  std::string_view line;
  bool last_announced = false;  // the last step kept was announced, not yet confirmed
  while (reader.next(line)) {
    const long number = reader.line_number();
    const auto journal = journal_entry(line);
    if (journal) line = journal->message;
    // The line's time: the journal's field, else the stamp the line starts with.
    const auto stamp_of = [&]() -> std::optional<LogStamp> {
      if (journal) return journal->stamp.resolution_ns > 0 ? std::optional(journal->stamp) : std::nullopt;
      return parse_log_stamp(trim(line));
    };
    std::optional<std::int64_t> size;
    bool step = false;
    bool announced = false;  // told before it is made: "(step)", which a failure may still undo
    bool initial = false;    // an initstepslew line, a step or a slew
    std::size_t at = 0;
    if ((at = line.find(kStepped)) != std::string_view::npos) {
      step = true;
      size = require_decimal_seconds(name, number, "step", trim(seconds_after(line, at, kStepped)));
    } else if ((at = line.find(kWrong)) != std::string_view::npos) {
      if (line.find(" seconds (step)", at) != std::string_view::npos) {
        step = announced = true;
        size = require_decimal_seconds(name, number, "step", trim(seconds_after(line, at, kWrong)));
      }
    } else if ((at = line.find(kInitial)) != std::string_view::npos) {
      initial = true;
      // initstepslew: "X seconds fast of true (step)" steps the clock back by X, "slow" forward.
      if (line.find(" of true (step)", at) != std::string_view::npos) {
        step = announced = true;
        size = require_decimal_seconds(name, number, "step", trim(seconds_after(line, at, kInitial)));
        if (line.find(" seconds fast of true", at) != std::string_view::npos) *size = -*size;
      }
    } else if (line.find(kLeap) != std::string_view::npos) {
      step = true;  // one second back for an inserted leap second, forward for a deleted one: unsaid
    } else if (line.find(kForward) != std::string_view::npos || line.find(kBackward) != std::string_view::npos) {
      step = true;
    } else if (line.find(kFailed) != std::string_view::npos) {
      ++result.chrony_lines;
      ++result.failed_steps;
      // The step it announced did not happen (the clock kept its reading: the stamps stay close).
      if (!result.steps.empty() && last_announced) {
        const auto stamp = stamp_of();
        if (stamp && std::llabs(stamp->ns - result.steps.back().time_ns) <= 2'000'000'000) result.steps.pop_back();
      }
      last_announced = false;
      continue;
    }
    if (step || initial || line.find("System clock") != std::string_view::npos)
      ++result.chrony_lines;
    else if (!is_blank(line))
      ++result.ignored_lines;
    if (!step) continue;
    const auto stamp = stamp_of();
    if (!stamp)
      throw_line_error(name, number,
                       "a chronyd step message without a time and zone at the start of the line: write "
                       "the log with `journalctl -o short-iso-precise` (or chronyd's own log)");
    ChronyStep s{number, stamp->ns, stamp->resolution_ns, size};
    // The same step told twice ("wrong by X (step)" then "stepped by X", or two log copies).
    if (!result.steps.empty()) {
      const auto& last = result.steps.back();
      const std::int64_t near = 2'000'000'000 + (size ? std::llabs(*size) : 0);
      if (last.size_ns == size && std::llabs(s.time_ns - last.time_ns) <= near) {
        last_announced = last_announced && announced;
        continue;
      }
    }
    result.steps.push_back(s);
    last_announced = announced;
  }
  if (result.chrony_lines == 0)
    throw_line_error(name, 0,
                     fmt::format("has no chronyd message about the system clock ({} other lines); is it "
                                 "chronyd's log?",
                                 result.ignored_lines));
  return result;
}

}  // namespace m2mlat::formats
