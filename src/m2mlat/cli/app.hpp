// Entry point of the m2mlat executable: parse the command line, run one subcommand, and turn
// exceptions into exit codes in this one place.
#pragma once

namespace m2mlat::cli {
int run(int argc, char** argv);
}  // namespace m2mlat::cli
