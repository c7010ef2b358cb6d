// Import throughput: data lines per second for each format the reference rig and m2mlat write, read
// from a file (in the page cache after the first pass) the way `m2mlat stats` and `import` read it.
//
// The .../timestamps cases are the lean path (read_timestamps: one int64 column per pin or label, no
// events); the others build the full result (a core::Event per line, or pairs with their events and
// the latency checks).
#include <fmt/format.h>

#include <cstdint>
#include <filesystem>
#include <stdexcept>
#include <string>
#include <variant>
#include <vector>

#include "m2mlat/formats/import_file.hpp"
#include "registry.hpp"
#include "workload.hpp"

namespace m2mlat::bench {

namespace {

// The number of timestamps or events an import returned, to check it read every line.
std::size_t count(const std::vector<formats::TimestampSeries>& series) {
  std::size_t n = 0;
  for (const auto& s : series) n += s.ns.size();
  return n;
}
std::size_t count(const formats::ImportedFile& file) {
  if (const auto* events = std::get_if<formats::EventImport>(&file.content)) return events->events.size();
  if (const auto* paired = std::get_if<formats::PairedImport>(&file.content)) return paired->pairs.size();
  return 0;
}

void expect(std::size_t got, std::size_t lines, const std::string& path) {
  if (got != lines)
    throw std::runtime_error(fmt::format("{}: imported {} records of {} lines", path, got, lines));
}

// One case: `import(path)` on the file `file`, which holds `lines` data lines.
template <typename Import>
void add_import(const std::string& name, std::string InputFiles::*file, std::size_t InputFiles::*lines,
                Import import) {
  add("import/" + name, [=](benchmark::State& state) {
    const auto& files = input_files();
    const auto& path = files.*file;
    const auto bytes = static_cast<std::int64_t>(std::filesystem::file_size(path));
    for (auto _ : state) {
      const auto result = import(path);
      expect(count(result), files.*lines, path);
      benchmark::DoNotOptimize(&result);
    }
    set_rate(state, files.*lines, "lines");
    state.SetBytesProcessed(static_cast<std::int64_t>(state.iterations()) * bytes);
  });
}

}  // namespace

void register_import_benchmarks() {
  using formats::Format;
  add_import("kernel_log/timestamps", &InputFiles::kernel_log, &InputFiles::kernel_log_lines,
             [](const std::string& path) { return formats::read_timestamps(path, Format::kernel_log); });
  add_import("kernel_log/events", &InputFiles::kernel_log, &InputFiles::kernel_log_lines,
             [](const std::string& path) { return formats::import_file(path, Format::kernel_log, {}); });
  add_import("rig_export_csv/timestamps", &InputFiles::rig_export_csv, &InputFiles::rig_export_lines,
             [](const std::string& path) { return formats::read_timestamps(path, Format::rig_export_csv); });
  add_import("rig_export_csv/events", &InputFiles::rig_export_csv, &InputFiles::rig_export_lines,
             [](const std::string& path) { return formats::import_file(path, Format::rig_export_csv, {}); });
  add_import("rig_paired_csv/pairs", &InputFiles::rig_paired_csv, &InputFiles::rig_paired_lines,
             [](const std::string& path) { return formats::import_file(path, Format::rig_paired_csv, {}); });
  add_import("events_csv/events", &InputFiles::events_csv, &InputFiles::events_csv_lines,
             [](const std::string& path) { return formats::import_file(path, Format::events_csv, {}); });
}

}  // namespace m2mlat::bench
