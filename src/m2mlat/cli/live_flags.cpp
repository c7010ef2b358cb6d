// Registration and conversion of the live views' flags.
#include "m2mlat/cli/live_flags.hpp"

#include <unistd.h>

#include "m2mlat/net/auth.hpp"

namespace m2mlat::cli {

void LiveFlags::add_to(CLI::App& sub, bool with_token_file) {
  auto* group = sub.add_option_group("live view");
  group->add_option("--dashboard", dashboard,
                    "Serve the live dashboard on ADDR:PORT (e.g. 127.0.0.1:8480; :0 = any free port)");
  if (with_token_file)
    group->add_option("--token-file", token_file, "The dashboard's bearer token (else $M2MLAT_TOKEN)");
  group->add_flag("--no-live", no_live, "Do not draw the live block on the terminal");
  group->add_option("--live-scenario", live_scenario,
                    "Pair this scenario live (default: the newest session's)");
  selection.add_to(sub);
  match.add_to(sub);
}

std::string token_flag_or_env(const std::string& token_file) {
  const auto token =
      net::load_token(token_file.empty() ? std::nullopt : std::optional<std::string>(token_file));
  return token.value_or("");
}

collect::LiveViewOptions LiveFlags::options(const std::string& store_path, const std::string& token,
                                            bool terminal) const {
  collect::LiveViewOptions o;
  o.store_path = store_path;
  o.pairing.selection = selection.selection();
  o.pairing.match = match.options();
  o.pairing.include_ambiguous = match.include_ambiguous;
  o.pairing.scenario = live_scenario;
  if (!dashboard.empty()) {
    collect::DashboardOptions d;
    collect::parse_listen_address(dashboard, d);
    // This subcommand's own --token-file, else the token it already read, else $M2MLAT_TOKEN.
    d.token = !token_file.empty() ? token_flag_or_env(token_file)
              : !token.empty()    ? token
                                  : token_flag_or_env("");
    o.dashboard = d;
  }
  o.terminal = terminal && !no_live;
  o.out = stdout;
  o.tty = ::isatty(STDOUT_FILENO) == 1;
  return o;
}

}  // namespace m2mlat::cli
