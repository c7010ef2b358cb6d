// `m2mlat setup <part>`: prepares this board for measuring. Each part is one entry in kParts below
// (a name, a line of help, and its attach function), so a new part is one function and one line.
// The parts' options are in setup_parts.cpp; their plans are in src/m2mlat/setup/.
#include <array>
#include <memory>

#include "m2mlat/cli/command.hpp"
#include "m2mlat/cli/setup_parts.hpp"
#include "m2mlat/core/error.hpp"

namespace m2mlat::cli {

namespace {

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
