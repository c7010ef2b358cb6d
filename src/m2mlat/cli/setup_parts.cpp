// `m2mlat setup chrony|gpio|irq|pin-chrony|agent|board`: each reads the system files its part looks at
// (under --root), asks the part for its plan (src/m2mlat/setup/) and applies it: every change is
// printed before it is made, --dry-run makes none, and a second run finds nothing to change.
// `setup chrony` writes where --output says (without it, it prints the configuration) and has no
// --root.
#include "m2mlat/cli/setup_parts.hpp"

#include <fmt/format.h>

#include <memory>
#include <string>

#include "m2mlat/setup/agent_config.hpp"
#include "m2mlat/setup/apply.hpp"
#include "m2mlat/setup/board.hpp"
#include "m2mlat/setup/chrony.hpp"
#include "m2mlat/setup/env_file.hpp"
#include "m2mlat/setup/gpio.hpp"
#include "m2mlat/setup/irq.hpp"
#include "m2mlat/setup/names.hpp"
#include "m2mlat/setup/pin_chrony.hpp"
#include "m2mlat/sync/chrony_config.hpp"

namespace m2mlat::cli {

namespace {

std::string read_or_empty(const std::string& root, const std::string& path) {
  std::string text;
  setup::read_target(root, path, text);
  return text;
}

void add_apply_options(CLI::App& sub, setup::ApplyOptions& o) {
  sub.add_flag("--dry-run", o.dry_run,
               "Print every change (files with content and diff, commands), make none");
  sub.add_option("--root", o.root, "Apply under this folder instead of / (commands are then not run)")
      ->capture_default_str();
}

int apply(const setup::Plan& plan, const setup::ApplyOptions& o) {
  return setup::apply_plan(plan, o).commands_failed > 0 ? 1 : 0;
}

void add_agent_options(CLI::App& sub, setup::AgentSetup& a) {
  sub.add_option("--role", a.role, "operator (its wheel is the cause) or vehicle (the effect)")->required();
  sub.add_option("--node", a.node, "This board's name (e.g. operator, vehicle)")->required();
  sub.add_option("--chip", a.chip, "The Hall sensor's GPIO chip: name, label or path (pinctrl-rp1 on a Pi 5)")
      ->required();
  sub.add_option("--line", a.line, "Its line: name or offset (GPIO16 = header pin 36)")->required();
  sub.add_option("--channel", a.channel, "The channel's name")->capture_default_str();
  sub.add_option("--edges", a.edges, "falling, rising or both")->capture_default_str();
  sub.add_option("--bias", a.bias, "as-is, pull-up, pull-down or disabled")->capture_default_str();
  sub.add_option("--refractory", a.refractory, "Drop edges this soon after a kept one")
      ->capture_default_str();
  sub.add_option("--source", a.source, "gpio, or sim to try the chain without a sensor")
      ->capture_default_str();
  sub.add_option("--listen", a.listen, "HOST:PORT the agent serves on (default of the unit: 127.0.0.1:8470)");
  sub.add_option("--token-file", a.token_file, "The bearer token's file (needed beyond loopback)");
  sub.add_option("--rt-priority", a.rt_priority, "SCHED_FIFO priority of the capture thread (1..99)");
  sub.add_option("--cpu", a.cpu, "CPU of the capture thread");
}

// `setup chrony`'s options; the configuration's own are sync::ChronyConfigOptions.
struct ChronySetup {
  std::string mode, role = "reference";
  sync::ChronyConfigOptions config;
  int cpu = -1;
  std::string output, dropin = std::string(sync::kChronyDropinPath);
  bool dry_run = false;
};

}  // namespace

Runner attach_setup_chrony(CLI::App& sub) {
  auto c = std::make_shared<ChronySetup>();
  sub.add_option("--mode", c->mode,
                 "co-referenced (one board serves the other), autonomous (public servers), gnss-pps")
      ->required();
  sub.add_option("--role", c->role, "co-referenced: reference (serves its clock) or peer (follows it)")
      ->capture_default_str();
  sub.add_option("--reference", c->config.reference, "peer: the reference board's address");
  sub.add_option("--reference-port", c->config.reference_port,
                 "peer: the reference's NTP port (default 123)");
  sub.add_option("--allow", c->config.allow,
                 "reference: who may synchronise (address or subnet; repeatable)");
  sub.add_option("--local-stratum", c->config.local_stratum, "reference: stratum of its own clock")
      ->capture_default_str();
  sub.add_option("--minpoll", c->config.minpoll, "peer: log2 of the shortest polling interval, s")
      ->capture_default_str();
  sub.add_option("--maxpoll", c->config.maxpoll, "peer: log2 of the longest polling interval, s")
      ->capture_default_str();
  sub.add_option("--server", c->config.servers, "autonomous: an NTP server (repeatable)");
  sub.add_option("--pool", c->config.pools,
                 "autonomous: an NTP pool (repeatable; default 2.debian.pool.ntp.org)");
  sub.add_option("--pps-device", c->config.pps_device, "gnss-pps: the PPS device")->capture_default_str();
  sub.add_option("--nmea", c->config.nmea, "gnss-pps: 'shm' (gpsd SHM 0) or gpsd's chrony socket path")
      ->capture_default_str();
  sub.add_option("--hwtimestamp", c->config.hwtimestamp,
                 "Use NIC hardware timestamps on this interface ('*': all)");
  sub.add_option("--makestep", c->config.makestep, "chrony's makestep: threshold (s) and limit")
      ->capture_default_str();
  sub.add_option("--driftfile", c->config.driftfile, "chrony's drift file")->capture_default_str();
  sub.add_option("--cpu", c->cpu, "Also pin chronyd to this CPU (systemd drop-in with CPUAffinity=)");
  sub.add_option("--dropin", c->dropin, "Where the drop-in goes")->capture_default_str();
  sub.add_option("--output", c->output,
                 "Write chrony.conf here (e.g. /etc/chrony/chrony.conf); default: print it");
  sub.add_flag("--dry-run", c->dry_run, "With --output: print every change, make none");
  return [c] {
    c->config.mode = sync::parse_sync_mode(c->mode);
    c->config.role = sync::parse_sync_role(c->role);
    const auto plan = setup::plan_chrony(c->config, c->output.empty() ? "chrony.conf" : c->output, c->cpu, c->dropin);
    if (!c->output.empty()) return apply(plan, setup::ApplyOptions{.root = "/", .dry_run = c->dry_run});
    // Without --output: the configuration (and the drop-in) on standard output, nothing written.
    fmt::print("{}", plan.steps.at(0).content);
    if (c->cpu >= 0) fmt::print("\n# {}:\n{}", c->dropin, plan.steps.at(1).content);
    return 0;
  };
}

Runner attach_setup_gpio(CLI::App& sub) {
  struct Options {
    setup::GpioSetup gpio;
    setup::ApplyOptions apply;
  };
  auto o = std::make_shared<Options>();
  sub.add_option("--user", o->gpio.users, "Add this user to the group gpio (repeatable)");
  add_apply_options(sub, o->apply);
  return
      [o] { return apply(setup::plan_gpio(o->gpio, read_or_empty(o->apply.root, "/etc/group")), o->apply); };
}

Runner attach_setup_irq(CLI::App& sub) {
  struct Options {
    setup::IrqSetup irq;
    setup::ApplyOptions apply;
  };
  auto o = std::make_shared<Options>();
  sub.add_option("--chip", o->irq.chip, "The line's GPIO chip: name, label or path")->required();
  sub.add_option("--line", o->irq.line, "The line: name or offset")->required();
  sub.add_option("--core", o->irq.core, "The CPU that takes its interrupt")->required();
  sub.add_option("--channel", o->irq.channel, "The channel's name in the agent's configuration")
      ->capture_default_str();
  sub.add_option(
      "--node", o->irq.node,
      "Keep it: M2MLAT_IRQ_CPU/NAME in /etc/m2mlat/<node>.env, applied at each start of the agent");
  add_apply_options(sub, o->apply);
  return [o] {
    if (!o->irq.node.empty()) setup::check_name("--node", o->irq.node);
    const auto env =
        o->irq.node.empty() ? std::string() : read_or_empty(o->apply.root, setup::env_path(o->irq.node));
    return apply(setup::plan_irq(o->irq, read_or_empty(o->apply.root, "/proc/interrupts"), env), o->apply);
  };
}

Runner attach_setup_pin_chrony(CLI::App& sub) {
  struct Options {
    int core = -1;
    setup::ApplyOptions apply;
  };
  auto o = std::make_shared<Options>();
  sub.add_option("--core", o->core, "The CPU chronyd runs on")->required();
  add_apply_options(sub, o->apply);
  return [o] { return apply(setup::plan_pin_chrony(o->core), o->apply); };
}

Runner attach_setup_agent(CLI::App& sub) {
  struct Options {
    setup::AgentSetup agent;
    setup::ApplyOptions apply;
  };
  auto o = std::make_shared<Options>();
  add_agent_options(sub, o->agent);
  add_apply_options(sub, o->apply);
  return [o] {
    setup::check_name("--node", o->agent.node);  // before it names a file
    return apply(setup::plan_agent(o->agent, read_or_empty(o->apply.root, setup::env_path(o->agent.node))),
                 o->apply);
  };
}

Runner attach_setup_board(CLI::App& sub) {
  struct Options {
    setup::BoardSetup board;
    std::string mode;
    setup::ApplyOptions apply;
  };
  auto o = std::make_shared<Options>();
  auto& b = o->board;
  add_agent_options(sub, b.agent);
  sub.add_option("--mode", o->mode, "Synchronisation: co-referenced, autonomous or gnss-pps")->required();
  sub.add_option(
      "--sync-role", b.sync_role,
      "co-referenced: reference or peer (default: the operator's board serves, the vehicle's follows)");
  sub.add_option("--reference", b.chrony.reference, "co-referenced peer: the reference board's address");
  sub.add_option("--allow", b.chrony.allow, "co-referenced reference: who may synchronise (repeatable)");
  sub.add_option("--server", b.chrony.servers, "autonomous: an NTP server (repeatable)");
  sub.add_option("--pool", b.chrony.pools, "autonomous: an NTP pool (repeatable)");
  sub.add_option("--pps-device", b.chrony.pps_device, "gnss-pps: the PPS device")->capture_default_str();
  sub.add_option("--nmea", b.chrony.nmea, "gnss-pps: 'shm' or gpsd's chrony socket")->capture_default_str();
  sub.add_option("--chrony-conf", b.chrony_conf, "Where chrony.conf goes")->capture_default_str();
  sub.add_option("--chrony-core", b.chrony_core, "Pin chronyd to this CPU");
  sub.add_option("--irq-core", b.irq_core,
                 "Route the wheel line's interrupt to this CPU (now and at each start)");
  sub.add_option("--user", b.users, "Add this user to the group gpio (repeatable)");
  add_apply_options(sub, o->apply);
  return [o] {
    o->board.chrony.mode = sync::parse_sync_mode(o->mode);
    setup::check_name("--node", o->board.agent.node);
    const auto& root = o->apply.root;
    setup::BoardState state{read_or_empty(root, "/etc/group"), read_or_empty(root, "/proc/interrupts"),
                            read_or_empty(root, setup::env_path(o->board.agent.node))};
    return apply(setup::plan_board(o->board, state), o->apply);
  };
}

}  // namespace m2mlat::cli
