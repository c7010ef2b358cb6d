// The agent unit's environment file, /etc/m2mlat/<node>.env (packaging/m2mlat-agent@.service reads
// it with EnvironmentFile=): KEY=VALUE lines. Several setup parts own different keys of the same
// file (agent: M2MLAT_LISTEN, M2MLAT_AGENT_ARGS; irq: M2MLAT_IRQ_CPU, M2MLAT_IRQ_NAME), so a part
// never rewrites the file: it sets its keys in the existing text and keeps every other line.
#pragma once

#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace m2mlat::setup {

using EnvKeys = std::vector<std::pair<std::string, std::string>>;

// `existing` with each key set to its value: a key's first KEY= line is replaced in place, further
// ones are removed, missing keys are appended; comments and other keys are kept. An empty
// `existing` gets a comment header naming `header_name`. The result ends with a newline.
std::string merge_env(std::string_view existing, const EnvKeys& keys, std::string_view header_name);

// The value of KEY in an environment file's text (the last assignment), if any.
std::optional<std::string> env_value(std::string_view text, std::string_view key);

// /etc/m2mlat/<node>.env
std::string env_path(std::string_view node);

}  // namespace m2mlat::setup
