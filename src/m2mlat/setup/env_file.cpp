// Setting keys in the agent unit's environment file without disturbing the others (env_file.hpp).
#include "m2mlat/setup/env_file.hpp"

#include <fmt/format.h>

#include <sstream>

namespace m2mlat::setup {

namespace {

// The KEY of a "KEY=VALUE" line (leading blanks skipped), or empty for comments and other lines.
std::string_view key_of(std::string_view line) {
  const auto start = line.find_first_not_of(" \t");
  if (start == std::string_view::npos || line[start] == '#') return {};
  line.remove_prefix(start);
  const auto eq = line.find('=');
  if (eq == std::string_view::npos) return {};
  auto key = line.substr(0, eq);
  while (!key.empty() && (key.back() == ' ' || key.back() == '\t')) key.remove_suffix(1);
  return key;
}

}  // namespace

std::string merge_env(std::string_view existing, const EnvKeys& keys, std::string_view header_name) {
  std::vector<bool> written(keys.size(), false);
  std::string out;
  if (existing.empty())
    out = fmt::format(
        "# Environment of {} (packaging/m2mlat-agent@.service), kept up to date by `m2mlat setup`.\n",
        header_name);
  std::size_t pos = 0;
  while (pos < existing.size()) {
    auto end = existing.find('\n', pos);
    if (end == std::string_view::npos) end = existing.size();
    const auto line = existing.substr(pos, end - pos);
    pos = end + 1;
    const auto key = key_of(line);
    bool replaced = false;
    for (std::size_t i = 0; i < keys.size() && !key.empty(); ++i) {
      if (keys[i].first != key) continue;
      if (!written[i]) out += fmt::format("{}={}\n", keys[i].first, keys[i].second);
      written[i] = true;
      replaced = true;
      break;
    }
    if (!replaced) {
      out += line;
      out += '\n';
    }
  }
  for (std::size_t i = 0; i < keys.size(); ++i)
    if (!written[i]) out += fmt::format("{}={}\n", keys[i].first, keys[i].second);
  return out;
}

std::optional<std::string> env_value(std::string_view text, std::string_view key) {
  std::optional<std::string> value;
  std::istringstream in{std::string(text)};
  for (std::string line; std::getline(in, line);) {
    if (key_of(line) != key) continue;
    value = line.substr(line.find('=') + 1);
  }
  return value;
}

std::string env_path(std::string_view node) { return fmt::format("/etc/m2mlat/{}.env", node); }

}  // namespace m2mlat::setup
