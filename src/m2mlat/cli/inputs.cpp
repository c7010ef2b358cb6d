// The input flags of the analysis subcommands, turned into the pipeline's inputs.
#include "m2mlat/cli/inputs.hpp"

#include "m2mlat/store/store.hpp"

namespace m2mlat::cli {

void InputFlags::add_to(CLI::App& sub, bool allow_rematch) {
  sub.add_option("inputs", inputs, "Campaign stores (.db) or data files (one scenario each)");
  sub.add_option("--scenario", scenarios,
                 "Only these scenarios of the stores (repeatable); with --cause-file and --effect-file: the "
                 "scenario's name (default: the folder of both files, else <cause>-<effect>)");
  sub.add_option("--cause-file", cause_file, "A file with the cause edges (with --effect-file)");
  sub.add_option("--effect-file", effect_file, "A file with the effect edges (with --cause-file)");
  sub.add_option("--format", format, "Format of the data files (default: detected)");
  if (allow_rematch)
    sub.add_flag("--rematch", rematch,
                 "Re-pair the events of a paired-results CSV instead of using its rows");
}

bool is_sqlite_file(const std::string& path) { return store::is_sqlite_database(path); }

analysis::PipelineInputs InputFlags::pipeline_inputs() const {
  analysis::PipelineInputs p;
  p.inputs = inputs;
  p.scenarios = scenarios;
  p.cause_file = cause_file;
  p.effect_file = effect_file;
  if (!format.empty()) p.format = formats::parse_format(format);
  p.rematch = rematch;
  return p;
}

}  // namespace m2mlat::cli
