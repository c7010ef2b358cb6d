// The rule that cuts an M2M event into stages (docs/breakdown.md): an ordered list of stages, each
// ended by a marker chosen by a selector, the last one ended by the effect. Written by the user in a
// stages file (`stats --stages FILE`), one stage a line:
//
//   operator_software = first operator:command after cause
//   network           = same key vehicle:receive
//   actuator          = effect
//
// The first stage starts at the cause, each next one where the previous ended, so the stages of an
// event add up to its M2M exactly.
#pragma once

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace m2mlat::analysis {

// How a stage's end marker is found.
enum class SelectorKind : std::uint8_t {
  first_after_cause,     // `first NODE:NAME after cause`: the first such marker at or after the cause
  first_after_previous,  // `first NODE:NAME after previous`: ... at or after the previous stage's end
  last_before_effect,    // `last NODE:NAME before effect`: the last such marker at or before the effect
  same_key,              // `same key NODE:NAME`: the such marker with the previous stage's marker's key
                         // (the first at or after the previous stage's end when the key repeats)
  effect,                // `effect`: the event's effect edge; the last stage, and only it
};

struct MarkerSelector {
  SelectorKind kind = SelectorKind::effect;
  std::string node;  // the marker's node ("operator", "vehicle"); empty for `effect`
  std::string name;  // the marker's name ("send", "packet", ...); empty for `effect`
};
// The selector as written in a stages file.
std::string to_string(const MarkerSelector& selector);

struct StageSpec {
  std::string name;     // the stage's name ([A-Za-z0-9_.-]+, unique in the rule)
  MarkerSelector end;   // what ends it
  long line = 0;        // where it was written (0: not from a file)
};

struct StageRule {
  std::vector<StageSpec> stages;  // at least two; the last ends at `effect`
  std::vector<std::string> names() const;
};

// Parses a stages file's text. Blank lines and lines starting with '#' are skipped. Throws
// core::Error(usage) "<file>:<line>: <field>: <problem>" naming the stage name or the selector.
StageRule parse_stage_rule(std::string_view text, std::string_view file);
// Reads and parses a stages file (core::Error no_input when it does not exist).
StageRule read_stage_rule(const std::string& path);

}  // namespace m2mlat::analysis
