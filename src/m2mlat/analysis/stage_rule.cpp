#include "m2mlat/analysis/stage_rule.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cstdint>

#include "m2mlat/core/error.hpp"
#include "m2mlat/core/printable.hpp"
#include "m2mlat/formats/fields.hpp"
#include "m2mlat/formats/input_text.hpp"

namespace m2mlat::analysis {

namespace {

[[noreturn]] void rule_error(std::string_view file, long line, std::string_view field, const std::string& what) {
  throw core::Error(core::ErrorKind::usage,
                    fmt::format("{}:{}: {}: {}", core::printable(file), line, field, what));
}

bool stage_name_ok(std::string_view name) {
  return !name.empty() && std::ranges::all_of(name, [](char c) {
    return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '_' ||
           c == '.' || c == '-';
  });
}

// The words of a selector, split at blanks.
std::vector<std::string_view> selector_words(std::string_view text) {
  std::vector<std::string_view> words;
  std::size_t i = 0;
  while (i < text.size()) {
    while (i < text.size() && (text[i] == ' ' || text[i] == '\t')) ++i;
    const std::size_t start = i;
    while (i < text.size() && text[i] != ' ' && text[i] != '\t') ++i;
    if (i > start) words.push_back(text.substr(start, i - start));
  }
  return words;
}

// "NODE:NAME" into the selector; both parts non-empty.
void parse_node_name(std::string_view word, MarkerSelector& s, std::string_view file, long line) {
  const auto colon = word.find(':');
  if (colon == std::string_view::npos || colon == 0 || colon + 1 == word.size() ||
      word.find(':', colon + 1) != std::string_view::npos)
    rule_error(file, line, "selector",
               fmt::format("'{}' is not NODE:NAME (a marker's node and name, e.g. operator:send)",
                           core::printable(word)));
  s.node = std::string(word.substr(0, colon));
  s.name = std::string(word.substr(colon + 1));
}

constexpr std::string_view kSelectorForms =
    "one of 'first NODE:NAME after cause', 'first NODE:NAME after previous', "
    "'last NODE:NAME before effect', 'same key NODE:NAME', 'effect'";

MarkerSelector parse_selector(std::string_view text, std::string_view file, long line) {
  const auto w = selector_words(text);
  MarkerSelector s;
  if (w.size() == 1 && w[0] == "effect") {
    s.kind = SelectorKind::effect;
  } else if (w.size() == 4 && w[0] == "first" && w[2] == "after" && (w[3] == "cause" || w[3] == "previous")) {
    s.kind = w[3] == "cause" ? SelectorKind::first_after_cause : SelectorKind::first_after_previous;
    parse_node_name(w[1], s, file, line);
  } else if (w.size() == 4 && w[0] == "last" && w[2] == "before" && w[3] == "effect") {
    s.kind = SelectorKind::last_before_effect;
    parse_node_name(w[1], s, file, line);
  } else if (w.size() == 3 && w[0] == "same" && w[1] == "key") {
    s.kind = SelectorKind::same_key;
    parse_node_name(w[2], s, file, line);
  } else {
    rule_error(file, line, "selector", fmt::format("'{}' is not {}", core::printable(text), kSelectorForms));
  }
  return s;
}

}  // namespace

std::string to_string(const MarkerSelector& s) {
  switch (s.kind) {
    case SelectorKind::first_after_cause: return fmt::format("first {}:{} after cause", s.node, s.name);
    case SelectorKind::first_after_previous: return fmt::format("first {}:{} after previous", s.node, s.name);
    case SelectorKind::last_before_effect: return fmt::format("last {}:{} before effect", s.node, s.name);
    case SelectorKind::same_key: return fmt::format("same key {}:{}", s.node, s.name);
    case SelectorKind::effect: return "effect";
  }
  return "effect";
}

std::vector<std::string> StageRule::names() const {
  std::vector<std::string> out;
  out.reserve(stages.size());
  for (const auto& s : stages) out.push_back(s.name);
  return out;
}

StageRule parse_stage_rule(std::string_view text, std::string_view file) {
  StageRule rule;
  formats::LineReader reader(text);
  std::string_view raw;
  long last_line = 0;
  while (reader.next(raw)) {
    const long line = reader.line_number();
    last_line = line;
    const auto content = formats::trim(raw);
    if (content.empty() || content.front() == '#') continue;
    if (!rule.stages.empty() && rule.stages.back().end.kind == SelectorKind::effect)
      rule_error(file, line, "stage", "after the stage that ends at the effect: the effect ends the last stage");
    const auto eq = content.find('=');
    if (eq == std::string_view::npos)
      rule_error(file, line, "stage", "expected 'NAME = SELECTOR' (e.g. 'network = same key vehicle:receive')");
    const auto name = formats::trim(content.substr(0, eq));
    if (!stage_name_ok(name))
      rule_error(file, line, "stage name",
                 fmt::format("'{}' is not a name of letters, digits, '_', '.' or '-'", core::printable(name)));
    if (std::ranges::any_of(rule.stages, [&](const StageSpec& s) { return s.name == name; }))
      rule_error(file, line, "stage name", fmt::format("'{}' is given twice", name));
    StageSpec spec{std::string(name), parse_selector(formats::trim(content.substr(eq + 1)), file, line), line};
    if (spec.end.kind == SelectorKind::same_key && rule.stages.empty())
      rule_error(file, line, "selector",
                 "'same key' needs a marker before it: the first stage starts at the cause, which has no key");
    rule.stages.push_back(std::move(spec));
  }
  if (rule.stages.empty()) rule_error(file, last_line, "stages", "no stage: write one 'NAME = SELECTOR' a line");
  if (rule.stages.back().end.kind != SelectorKind::effect)
    rule_error(file, rule.stages.back().line, "selector",
               "the last stage must end at the effect ('NAME = effect'), so that the stages add up to the M2M");
  if (rule.stages.size() < 2)
    rule_error(file, rule.stages.back().line, "stages",
               "one stage ending at the effect is the M2M itself: name at least one marker before it");
  return rule;
}

StageRule read_stage_rule(const std::string& path) {
  const auto input = formats::InputText::read_file(path);
  return parse_stage_rule(input.text(), input.name());
}

}  // namespace m2mlat::analysis
