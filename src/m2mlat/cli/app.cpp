// Builds the CLI from the subcommand table and maps errors to exit codes.
#include "m2mlat/cli/app.hpp"

#include <fmt/format.h>

#include <iostream>
#include <string>
#include <string_view>

#include "m2mlat/cli/command.hpp"
#include "m2mlat/core/error.hpp"
#include "m2mlat/core/heap.hpp"
#include "m2mlat/core/printable.hpp"
#include "m2mlat/core/version.hpp"

namespace m2mlat::cli {

namespace {

// The first argument that is not an option: the subcommand (the top level has only flags, none of
// which takes a value). Empty when there is none.
std::string_view subcommand_named(int argc, char** argv) {
  for (int i = 1; i < argc; ++i)
    if (argv[i][0] != '-') return argv[i];
  return {};
}

}  // namespace

int run(int argc, char** argv) {
  core::return_large_blocks_when_freed();
  CLI::App app{"m2mlat: measure Motion-to-Motion latency between two boards (cause -> effect edges)",
               "m2mlat"};
  app.set_version_flag("--version", std::string("m2mlat ") + core::kVersion);
  app.require_subcommand(1);
  app.fallthrough(false);

  // Every subcommand is listed (for --help and the error on an unknown one), but only the one named
  // on the command line gets its options: building all of them cost about 9 M instructions (callgrind),
  // a sixth of an idle `record`'s whole run, paid again by every command.
  const std::string_view named = subcommand_named(argc, argv);
  std::vector<std::pair<CLI::App*, Runner>> runners;
  for (const auto& command : commands()) {
    CLI::App* sub = app.add_subcommand(std::string(command.name), std::string(command.summary));
    if (command.name == named) runners.emplace_back(sub, command.attach(*sub));
  }

  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForAllHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForVersion& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    app.exit(e);  // prints the usage error
    return core::exit_code(core::ErrorKind::usage);
  }

  try {
    for (auto& [sub, runner] : runners)
      if (sub->parsed()) return runner();
  } catch (const core::Error& e) {
    // Messages quote input (file names, node names, fields): shown escaped (core/printable.hpp).
    std::cerr << "m2mlat: error: " << core::printable(e.what()) << '\n';
    return core::exit_code(e.kind());
  } catch (const std::exception& e) {
    std::cerr << "m2mlat: internal error: " << core::printable(e.what()) << '\n';
    return core::exit_code(core::ErrorKind::internal);
  }
  return core::exit_code(core::ErrorKind::usage);
}

}  // namespace m2mlat::cli
