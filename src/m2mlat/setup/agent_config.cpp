// The agent configuration part of `m2mlat setup` (agent_config.hpp).
#include "m2mlat/setup/agent_config.hpp"

#include <fmt/format.h>

#include "m2mlat/core/error.hpp"
#include "m2mlat/setup/names.hpp"

namespace m2mlat::setup {

namespace {

bool loopback(std::string_view listen) {
  return listen.starts_with("127.") || listen.starts_with("localhost:") || listen.starts_with("[::1]:");
}

void check_choice(std::string_view option, std::string_view value,
                  std::initializer_list<std::string_view> choices) {
  for (auto c : choices)
    if (value == c) return;
  std::string list;
  for (auto c : choices) list += (list.empty() ? "" : ", ") + std::string(c);
  throw core::Error(core::ErrorKind::usage, fmt::format("{} '{}': use {}", option, value, list));
}

}  // namespace

std::string_view agent_role(std::string_view role) {
  if (role == "operator") return "cause";
  if (role == "vehicle") return "effect";
  throw core::Error(
      core::ErrorKind::usage,
      fmt::format("--role '{}': use operator (the cause board) or vehicle (the effect board)", role));
}

std::string agent_config_path(std::string_view node) { return fmt::format("/etc/m2mlat/{}.toml", node); }
std::string agent_unit(std::string_view node) { return fmt::format("m2mlat-agent@{}", node); }

std::string agent_config_toml(const AgentSetup& s) {
  const auto role = agent_role(s.role);
  check_name("--node", s.node);
  check_name("--channel", s.channel);
  check_value("--chip", s.chip);
  check_value("--line", s.line);
  check_value("--refractory", s.refractory);
  check_choice("--edges", s.edges, {"falling", "rising", "both"});
  check_choice("--bias", s.bias, {"as-is", "pull-up", "pull-down", "disabled"});
  check_choice("--source", s.source, {"gpio", "sim"});
  std::string t = fmt::format(
      "# {}: the m2mlat agent of this board ({} board), written by `m2mlat setup agent`\n"
      "# (docs/field-guide.md). Read by {}.service as `m2mlat agent --config {}`;\n"
      "# the keys are those of `m2mlat record --config` (docs/capture.md).\n"
      "node = \"{}\"\n"
      "role = \"{}\"\n"
      "source = \"{}\"\n"
      "\n"
      "# The Hall sensor: A3144 output, pulled up to 3.3 V, low while a magnet passes.\n"
      "[[channel]]\n"
      "name = \"{}\"\n"
      "chip = \"{}\"\n"
      "line = \"{}\"\n"
      "edges = \"{}\"\n"
      "bias = \"{}\"\n"
      "refractory = \"{}\"\n",
      agent_config_path(s.node), s.role, agent_unit(s.node), agent_config_path(s.node), s.node, role,
      s.source, s.channel, s.chip, s.line, s.edges, s.bias, s.refractory);
  if (s.rt_priority > 0 || s.cpu >= 0) {
    if (s.rt_priority > 99)
      throw core::Error(core::ErrorKind::usage, fmt::format("--rt-priority {}: use 1..99", s.rt_priority));
    t += "\n# The capture thread: SCHED_FIFO priority and CPU (the unit grants CAP_SYS_NICE).\n[rt]\n";
    if (s.rt_priority > 0) t += fmt::format("priority = {}\n", s.rt_priority);
    if (s.cpu >= 0) t += fmt::format("cpu = {}\n", s.cpu);
  }
  return t;
}

EnvKeys agent_env_keys(const AgentSetup& s) {
  EnvKeys keys;
  if (!s.listen.empty()) {
    check_value("--listen", s.listen);
    if (!loopback(s.listen) && s.token_file.empty())
      throw core::Error(
          core::ErrorKind::usage,
          fmt::format("--listen {}: an agent reachable from other machines needs --token-file", s.listen));
    keys.emplace_back("M2MLAT_LISTEN", s.listen);
  }
  if (!s.token_file.empty()) {
    check_value("--token-file", s.token_file);
    if (s.token_file.find(' ') != std::string::npos)
      throw core::Error(core::ErrorKind::usage, fmt::format("--token-file '{}': no spaces", s.token_file));
    // Quoted: systemd's EnvironmentFile= strips the quotes (and ExecStart= splits $M2MLAT_AGENT_ARGS at
    // spaces), and the file stays a valid shell script.
    keys.emplace_back("M2MLAT_AGENT_ARGS", "\"--token-file " + s.token_file + "\"");
  }
  return keys;
}

Plan plan_agent(const AgentSetup& s, std::string_view current_env) {
  Plan plan;
  plan.part = "agent";
  plan.steps.push_back(
      file_step(agent_config_path(s.node), agent_config_toml(s),
                fmt::format("the agent's configuration ({} board, node {})", s.role, s.node)));
  const auto keys = agent_env_keys(s);
  if (!keys.empty())
    plan.steps.push_back(file_step(env_path(s.node), merge_env(current_env, keys, agent_unit(s.node)),
                                   "where the agent listens and its options"));
  if (!s.token_file.empty())
    plan.notes.push_back(fmt::format(
        "the token file {0} must exist, the same on the coordinator's side, and be the agent's secret "
        "(owned by m2mlat with mode 0600, or by root:m2mlat with 0640; others are refused), e.g. "
        "`(umask 077; head -c 24 /dev/urandom | base64 > {0}); chown root:m2mlat {0}; chmod 640 {0}`",
        s.token_file));
  plan.notes.push_back(
      fmt::format("check it (pass a magnet): m2mlat record --config {} --store /tmp/try.db --count 1",
                  agent_config_path(s.node)));
  plan.notes.push_back(fmt::format("start it: systemctl enable --now {}", agent_unit(s.node)));
  plan.notes.push_back(fmt::format("after a change: systemctl restart {}", agent_unit(s.node)));
  return plan;
}

}  // namespace m2mlat::setup
