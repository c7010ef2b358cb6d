// The flags of the live views (`m2mlat collect`, `m2mlat watch`): the dashboard's address and
// token, whether to draw the terminal block, and which channels to pair how (the same selection and
// matcher flags as `m2mlat stats`, so the live numbers are the offline ones).
#pragma once

#include <CLI/CLI.hpp>
#include <string>

#include "m2mlat/cli/analysis_options.hpp"
#include "m2mlat/collect/live_view.hpp"

namespace m2mlat::cli {

struct LiveFlags {
  std::string dashboard;      // ADDR:PORT; empty = no dashboard
  std::string token_file;     // the dashboard's bearer token (else $M2MLAT_TOKEN); needed off loopback
  bool no_live = false;       // no terminal block
  std::string live_scenario;  // pair this scenario (default: the newest session's)
  SelectionFlags selection;
  MatchFlags match;
  ChainFlags chains;                 // a scenario with gyroscope traces: the full loop's chains
  std::string loop_window = "1min";  // ... over the traces' last window
  std::string stages_file;           // the stage rule of the live breakdown (docs/breakdown.md); empty: none
  std::string stages_window = "30s";  // a pair's join redone while it is this recent
  // `with_token_file`: false where the subcommand already has --token-file (collect: the agents' and
  // the dashboard's token are then the same).
  void add_to(CLI::App& sub, bool with_token_file = true);
  // The live view's options for `store_path`; `token` is the token read by the subcommand (may be
  // empty), used if this has no --token-file of its own. `terminal`: draw the block (stdout).
  collect::LiveViewOptions options(const std::string& store_path, const std::string& token,
                                   bool terminal) const;
};

// A bearer token by the agent's rules (net::load_token): the file's first line, else $M2MLAT_TOKEN, else "".
std::string token_flag_or_env(const std::string& token_file);

}  // namespace m2mlat::cli
