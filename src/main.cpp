// The m2mlat executable: only dispatches to the subcommand table (src/m2mlat/cli/).
#include "m2mlat/cli/app.hpp"

int main(int argc, char** argv) { return m2mlat::cli::run(argc, argv); }
