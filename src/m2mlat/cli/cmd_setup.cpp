// `m2mlat setup <part>`: prepares this board for measuring. Each part is one entry in kParts below
// (a name, a line of help, and its attach function), so a new part is one function and one line.
//   setup chrony: writes chrony.conf for a synchronisation mode (sync::chrony_config) and, with
//                 --cpu, a systemd drop-in pinning chronyd to a core. Without --output it only
//                 prints the configuration; --dry-run prints every change without making it.
//   setup gpio | irq | pin-chrony | agent | board: setup_parts.cpp; their plans are in src/m2mlat/setup/.
#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <filesystem>
#include <fstream>
#include <memory>
#include <sstream>

#include "m2mlat/cli/command.hpp"
#include "m2mlat/cli/setup_parts.hpp"
#include "m2mlat/core/error.hpp"
#include "m2mlat/setup/apply.hpp"
#include "m2mlat/sync/chrony_config.hpp"

namespace m2mlat::cli {

namespace {

// ---- writing files, announcing each change first ----

std::string read_file_if_any(const std::string& path) {
  std::ifstream in(path);
  if (!in) return {};
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

// Prints what it is about to do, then (unless dry_run) does it: a backup of a different existing
// file (<path>.m2mlat-backup), then the new content (setup::replace_file).
void write_file(const std::string& path, const std::string& content, bool dry_run) {
  namespace fs = std::filesystem;
  const bool exists = fs::exists(path);
  if (exists && read_file_if_any(path) == content) {
    fmt::print("{}: unchanged\n", path);
    return;
  }
  const fs::path dir = fs::path(path).parent_path();
  if (!dir.empty() && !fs::exists(dir))
    fmt::print("{} directory {}\n", dry_run ? "would create" : "creating", dir.string());
  if (exists) fmt::print("{} {} to {}.m2mlat-backup\n", dry_run ? "would copy" : "copying", path, path);
  fmt::print("{} {} ({} lines):\n", dry_run ? "would write" : "writing", path,
             std::count(content.begin(), content.end(), '\n'));
  std::istringstream lines(content);
  for (std::string line; std::getline(lines, line);) fmt::print("  | {}\n", line);
  if (dry_run) return;
  setup::replace_file(path, content, 0644);
}

// ---- setup chrony ----

struct ChronySetup {
  std::string mode, role = "reference";
  sync::ChronyConfigOptions config;
  int cpu = -1;
  std::string output, dropin = std::string(sync::kChronyDropinPath);
  bool dry_run = false;
};

int run_setup_chrony(ChronySetup& c) {
  c.config.mode = sync::parse_sync_mode(c.mode);
  c.config.role = sync::parse_sync_role(c.role);
  const std::string conf = sync::chrony_config(c.config);
  if (c.output.empty()) {
    fmt::print("{}", conf);
    if (c.cpu >= 0) fmt::print("\n# {}:\n{}", c.dropin, sync::chrony_cpu_dropin(c.cpu));
    return 0;
  }
  write_file(c.output, conf, c.dry_run);
  if (c.cpu >= 0) write_file(c.dropin, sync::chrony_cpu_dropin(c.cpu), c.dry_run);
  fmt::print(
      "\nthen: check it with `chronyd -p -f {}`, restart chronyd{}, and watch `m2mlat clock --watch`\n",
      c.output,
      c.cpu >= 0 ? " (systemctl daemon-reload && systemctl restart chrony)" : " (systemctl restart chrony)");
  return 0;
}

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
  return [c] { return run_setup_chrony(*c); };
}

// ---- the parts ----

struct SetupPart {
  std::string_view name;
  std::string_view summary;
  Attach attach;
};

constexpr std::array kParts{
    SetupPart{"chrony", "Write chrony.conf for a synchronisation mode (and pin chronyd to a core)",
              &attach_setup_chrony},
    SetupPart{"gpio", "udev rule and group gpio for /dev/gpiochip*, and a user in it", &attach_setup_gpio},
    SetupPart{"irq", "Route a GPIO line's interrupt to a core (now, and at each start of the agent)",
              &attach_setup_irq},
    SetupPart{"pin-chrony", "Keep chronyd on one core (systemd drop-in)", &attach_setup_pin_chrony},
    SetupPart{"agent", "Write the agent's configuration /etc/m2mlat/<node>.toml for its role",
              &attach_setup_agent},
    SetupPart{"board", "All of the above for one board, chrony included", &attach_setup_board},
};

}  // namespace

Runner attach_setup(CLI::App& sub) {
  sub.require_subcommand(1);
  auto runners = std::make_shared<std::vector<std::pair<CLI::App*, Runner>>>();
  for (const auto& part : kParts) {
    CLI::App* p = sub.add_subcommand(std::string(part.name), std::string(part.summary));
    runners->emplace_back(p, part.attach(*p));
  }
  return [runners] {
    for (auto& [p, run] : *runners)
      if (p->parsed()) return run();
    throw core::Error(core::ErrorKind::usage, "setup needs a part (see m2mlat setup --help)");
  };
}

}  // namespace m2mlat::cli
