// Registration and conversion of the live views' flags.
#include "m2mlat/cli/live_flags.hpp"

#include <unistd.h>

#include "m2mlat/analysis/stage_rule.hpp"
#include "m2mlat/cli/duration_flag.hpp"
#include "m2mlat/core/error.hpp"
#include "m2mlat/net/auth.hpp"
#include "m2mlat/onset/detectors.hpp"

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
  group
      ->add_option("--loop-window", loop_window,
                   "Full loop: chain the gyroscope traces' last window on each refresh (cost bounded by it)")
      ->capture_default_str();
  group->add_option("--stages", stages_file,
                    "Stage rule (as `stats --stages`): show each scenario's live breakdown over the markers "
                    "collected so far (docs/breakdown.md)");
  group
      ->add_option("--stages-window", stages_window,
                   "Join a pair to late markers again while the newest data is less than this past its effect")
      ->capture_default_str();
  selection.add_to(sub);
  match.add_to(sub);
  chains.add_to(sub);
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
  o.pairing.chains = !chains.no_chains;
  static_cast<void>(onset::detector(chains.detector));  // an unknown name is a usage error now
  o.pairing.detector = chains.detector;
  o.pairing.led_channel = chains.led_channel;
  o.pairing.photo_channel = chains.photo_channel;
  o.pairing.default_led_bound = duration_flag("--led-bound", chains.led_bound);
  o.pairing.loop_window = duration_flag("--loop-window", loop_window);
  if (o.pairing.loop_window.count() <= 0 || o.pairing.default_led_bound.count() < 0)
    throw core::Error(core::ErrorKind::usage, "--loop-window must be positive, --led-bound not negative");
  if (!stages_file.empty()) {
    o.pairing.stages = analysis::read_stage_rule(stages_file);  // a bad rule: usage error, nothing started
    o.pairing.stages_window = duration_flag("--stages-window", stages_window);
    if (o.pairing.stages_window.count() <= 0)
      throw core::Error(core::ErrorKind::usage, "--stages-window must be positive");
  }
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
