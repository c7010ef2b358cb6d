// The subcommand table. Add a subcommand by writing cmd_<name>.cpp and one line here.
#include <array>

#include "m2mlat/cli/command.hpp"

namespace m2mlat::cli {

Runner attach_help(CLI::App& sub);

namespace {
constexpr std::array kCommands{
    Command{"help", "List the subcommands with a line on each", &attach_help},
};
}  // namespace

std::span<const Command> commands() { return kCommands; }

}  // namespace m2mlat::cli
