// The subcommand table: every subcommand is one entry, defined in its own file (cmd_<name>.cpp).
// Help text and `m2mlat help` are generated from this table.
#pragma once

#include <CLI/CLI.hpp>
#include <functional>
#include <span>
#include <string_view>

namespace m2mlat::cli {

// Called once when the subcommand's options are registered; returns the function that runs it
// after parsing. The runner returns the process exit code; errors are thrown as core::Error.
using Runner = std::function<int()>;
using Attach = Runner (*)(CLI::App& sub);

struct Command {
  std::string_view name;
  std::string_view summary;  // one line, shown in `m2mlat --help` and `m2mlat help`
  Attach attach;
};

std::span<const Command> commands();

}  // namespace m2mlat::cli
