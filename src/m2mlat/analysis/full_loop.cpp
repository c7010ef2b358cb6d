// The full-loop quantities of the full-loop rig's files, and their summaries.
#include "m2mlat/analysis/full_loop.hpp"

#include <filesystem>

#include "m2mlat/formats/import_file.hpp"
#include "m2mlat/store/store.hpp"

namespace m2mlat::analysis {

namespace {

using formats::FullLoopRow;

LoopValue excluded(LoopExclusion why) { return LoopValue{std::nullopt, why}; }

// later - earlier of two columns; `ordered`: a negative difference is impossible.
LoopValue difference(const FullLoopRow& row, std::size_t later, std::size_t earlier, bool ordered) {
  const auto& a = row.ns[later];
  const auto& b = row.ns[earlier];
  if (!a || !b) return excluded(LoopExclusion::missing);
  std::int64_t d = 0;
  if (__builtin_sub_overflow(*a, *b, &d)) return excluded(LoopExclusion::overflow);
  if (ordered && d < 0) return excluded(LoopExclusion::impossible);
  return LoopValue{d, LoopExclusion::missing};
}

void add(LoopSeries& series, const LoopValue& value, std::int64_t line) {
  if (value.ns) {
    series.ns.push_back(*value.ns);
    series.lines.push_back(line);
  } else {
    ++series.excluded.at(static_cast<std::size_t>(value.why));
  }
}

void summarise(LoopSeries& series, LoopQuantity quantity, const stats::SummaryOptions& options) {
  series.summary = stats::summarize(series.ns, series.lines, options_for(quantity, options));
}

}  // namespace

stats::SummaryOptions options_for(LoopQuantity quantity, const stats::SummaryOptions& options) {
  stats::SummaryOptions out = options;
  if (!is_latency(quantity)) out.thresholds.clear();
  return out;
}

std::string_view label(LoopQuantity quantity) {
  constexpr std::array<std::string_view, kLoopQuantities.size()> kLabels{"M2M", "G2G", "E2E",
                                                                         "vehicle motion", "station motion"};
  return kLabels.at(static_cast<std::size_t>(quantity));
}

std::string_view key(LoopQuantity quantity) {
  constexpr std::array<std::string_view, kLoopQuantities.size()> kKeys{"m2m", "g2g", "e2e", "vehicle_motion",
                                                                       "station_motion"};
  return kKeys.at(static_cast<std::size_t>(quantity));
}

std::string_view key(LoopExclusion exclusion) {
  constexpr std::array<std::string_view, kLoopExclusions> kKeys{"missing", "impossible", "overflow"};
  return kKeys.at(static_cast<std::size_t>(exclusion));
}

std::array<LoopValue, kLoopQuantities.size()> loop_values(const FullLoopRow& row) {
  using namespace formats;
  std::array<LoopValue, kLoopQuantities.size()> v;
  auto& m2m = v[static_cast<std::size_t>(LoopQuantity::m2m)];
  auto& g2g = v[static_cast<std::size_t>(LoopQuantity::g2g)];
  m2m = difference(row, kVehicleGyOn, kStationGyOn, false);
  g2g = difference(row, kPhototransistor, kLedOn, true);
  auto& e2e = v[static_cast<std::size_t>(LoopQuantity::e2e)];
  if (!m2m.ns) {
    e2e = excluded(m2m.why);
  } else if (!g2g.ns) {
    e2e = excluded(g2g.why);
  } else {
    std::int64_t sum = 0;
    e2e = __builtin_add_overflow(*m2m.ns, *g2g.ns, &sum) ? excluded(LoopExclusion::overflow)
                                                         : LoopValue{sum, LoopExclusion::missing};
  }
  v[static_cast<std::size_t>(LoopQuantity::vehicle_motion)] =
      difference(row, kVehicleGyOff, kVehicleGyOn, true);
  v[static_cast<std::size_t>(LoopQuantity::station_motion)] =
      difference(row, kStationGyOff, kStationGyOn, true);
  return v;
}

FullLoopResult analyse_full_loop(std::string scenario, std::string file, const formats::FullLoopImport& rows,
                                 const stats::SummaryOptions& options) {
  FullLoopResult result;
  result.scenario = std::move(scenario);
  result.file = std::move(file);
  result.format = formats::Format::full_loop_csv;
  result.events = rows.rows.size();
  for (auto& q : result.quantities) q.emplace();
  for (const auto& row : rows.rows) {
    const auto values = loop_values(row);
    for (std::size_t k = 0; k < values.size(); ++k) add(*result.quantities[k], values[k], row.line);
  }
  for (std::size_t k = 0; k < result.quantities.size(); ++k)
    summarise(*result.quantities[k], kLoopQuantities[k], options);
  return result;
}

FullLoopResult analyse_camera_latency(std::string scenario, std::string file,
                                      const formats::CameraLatencyImport& latencies,
                                      const stats::SummaryOptions& options) {
  FullLoopResult result;
  result.scenario = std::move(scenario);
  result.file = std::move(file);
  result.format = formats::Format::camera_latency;
  result.events = latencies.latency_ns.size();
  auto& g2g = result.quantities[static_cast<std::size_t>(LoopQuantity::g2g)].emplace();
  for (std::size_t i = 0; i < latencies.latency_ns.size(); ++i) {
    const std::int64_t ns = latencies.latency_ns[i];
    add(g2g, ns < 0 ? excluded(LoopExclusion::impossible) : LoopValue{ns, LoopExclusion::missing},
        latencies.lines[i]);
  }
  summarise(g2g, LoopQuantity::g2g, options);
  return result;
}

std::vector<FullLoopResult> take_full_loop_files(std::vector<std::string>& inputs,
                                                 std::optional<formats::Format> format,
                                                 const stats::SummaryOptions& options) {
  const auto is_loop = [](std::optional<formats::Format> f) {
    return f == formats::Format::full_loop_csv || f == formats::Format::camera_latency;
  };
  if (format && !is_loop(format)) return {};
  std::vector<FullLoopResult> results;
  std::vector<std::string> rest;
  for (auto& path : inputs) {
    // Stores are recognised through SQLite (safe beside open connections); a raw read of anything
    // else is then safe too (docs/store.md).
    std::error_code ec;  // unreadable: not taken here, the pipeline names the problem
    const bool take = format ? true
                             : path != "-" && std::filesystem::is_regular_file(path, ec) &&
                                   !store::is_sqlite_database(path) &&
                                   is_loop(formats::detect_file_format(path));
    if (!take) {
      rest.push_back(std::move(path));
      continue;
    }
    auto file = formats::import_file(path, format, {});
    auto scenario = std::filesystem::path(path).stem().string();
    if (const auto* rows = std::get_if<formats::FullLoopImport>(&file.content))
      results.push_back(analyse_full_loop(std::move(scenario), path, *rows, options));
    else
      results.push_back(analyse_camera_latency(
          std::move(scenario), path, std::get<formats::CameraLatencyImport>(file.content), options));
  }
  inputs = std::move(rest);
  return results;
}

}  // namespace m2mlat::analysis
