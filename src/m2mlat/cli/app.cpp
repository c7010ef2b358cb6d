// Builds the CLI from the subcommand table and maps errors to exit codes.
#include "m2mlat/cli/app.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <iostream>
#include <string>
#include <string_view>
#include <vector>

#include "m2mlat/cli/command.hpp"
#include "m2mlat/core/error.hpp"
#include "m2mlat/core/heap.hpp"
#include "m2mlat/core/nearest.hpp"
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

// Every long option of `app`, with those of its option groups (unnamed sub-apps), as "--name".
void long_options(const CLI::App& app, std::vector<std::string>& out) {
  for (const auto* option : app.get_options())
    for (const auto& name : option->get_lnames()) out.push_back("--" + name);
  for (const auto* group : app.get_subcommands([](const CLI::App* a) { return a->get_name().empty(); }))
    long_options(*group, out);
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

  if (!named.empty()) {
    std::vector<std::string> names;
    for (const auto& command : commands()) names.emplace_back(command.name);
    if (std::find(names.begin(), names.end(), named) == names.end()) {
      std::cerr << "m2mlat: error: '" << core::printable(named) << "' is not a subcommand"
                << core::printable(core::did_you_mean(named, names)) << "; `m2mlat help` lists them\n";
      return core::exit_code(core::ErrorKind::usage);
    }
  }
  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForAllHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForVersion& e) {
    return app.exit(e);
  } catch (const CLI::ExtrasError& e) {
    // An option or argument the subcommand has not: name it, and the nearest option it has.
    app.exit(e);
    if (!runners.empty()) {
      std::vector<std::string> options;
      long_options(*runners.front().first, options);
      for (int i = 1; i < argc; ++i)
        if (const std::string_view arg = argv[i]; arg.starts_with("--"))
          if (const auto best = core::nearest(arg.substr(0, arg.find('=')), options))
            std::cerr << "did you mean '" << *best << "' for '" << core::printable(arg) << "'?\n";
    }
    return core::exit_code(core::ErrorKind::usage);
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
