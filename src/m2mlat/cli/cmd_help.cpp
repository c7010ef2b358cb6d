// `m2mlat help`: the subcommand table as a list.
#include <fmt/format.h>

#include "m2mlat/cli/command.hpp"

namespace m2mlat::cli {

Runner attach_help(CLI::App& /*sub*/) {
  return [] {
    fmt::print("usage: m2mlat <subcommand> [options]   (m2mlat <subcommand> --help for its options)\n\n");
    for (const auto& command : commands()) fmt::print("  {:<10} {}\n", command.name, command.summary);
    return 0;
  };
}

}  // namespace m2mlat::cli
