// Tables, JSON, CSV and figure data of the full-loop files.
#include "m2mlat/report/full_loop_view.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "m2mlat/report/scenario_json.hpp"
#include "m2mlat/report/scenario_text.hpp"
#include "m2mlat/report/table.hpp"

namespace m2mlat::report {

namespace {

using analysis::FullLoopResult;
using analysis::LoopExclusion;
using analysis::LoopQuantity;

}  // namespace

const std::vector<stats::ThresholdShare>* full_loop_thresholds(std::span<const FullLoopResult> results) {
  for (const auto& r : results)
    for (const auto q : analysis::kLoopQuantities)
      if (const auto* s = r.find(q)) return &s->summary.thresholds;
  return nullptr;
}

std::vector<std::string> full_loop_notes(const FullLoopResult& r) {
  std::vector<std::string> out;
  const auto* m2m = r.find(LoopQuantity::m2m);
  if (m2m == nullptr || m2m->summary.n == 0 || !(m2m->summary.median_ms < kSmallM2MMs)) return out;
  const bool negative = m2m->summary.min && m2m->summary.min->ns < 0;
  out.push_back(fmt::format(
      "{}: M2M median {:.1f} ms{}: what a baseline gives (both gyroscopes on one body, true M2M = 0; the "
      "onset detectors' spread makes some negative); a teleoperated vehicle's M2M holds the network and the "
      "actuator and cannot be this small: check the roles or the boards' clocks",
      r.scenario, m2m->summary.median_ms, negative ? ", some samples negative" : ""));
  return out;
}

std::vector<std::string> full_loop_header(std::span<const FullLoopResult> results) {
  std::vector<std::string> header{"scenario", "quantity", "events", "excluded (missing/impossible/overflow)",
                                  "n",        "median",   "IQR",    "mean",
                                  "sd",       "min",      "max",    "P95"};
  if (const auto* t = full_loop_thresholds(results))
    for (const auto& share : *t)
      header.push_back(fmt::format("> {:g} ms", static_cast<double>(share.threshold.count()) / 1e6));
  return header;
}

std::vector<std::vector<std::string>> full_loop_rows(std::span<const FullLoopResult> results) {
  std::vector<std::vector<std::string>> rows;
  for (const auto& r : results)
    for (const auto q : analysis::kLoopQuantities) {
      const auto* s = r.find(q);
      if (s == nullptr) continue;
      std::vector<std::string> row{
          r.scenario, std::string(analysis::label(q)), std::to_string(r.events),
          fmt::format("{} / {} / {}", s->excluded[0], s->excluded[1], s->excluded[2])};
      for (auto& cell : summary_cells(s->summary)) row.push_back(std::move(cell));
      rows.push_back(std::move(row));
    }
  return rows;
}

std::string full_loop_table(std::span<const FullLoopResult> results) {
  const auto header = full_loop_header(results);
  Table table(header);
  for (auto& row : full_loop_rows(results)) {
    row.resize(header.size(), "-");
    table.add_row(std::move(row));
  }
  std::string text =
      "full loop (ms): M2M = VEHICLE_GY_ON - STATION_GY_ON, G2G = PHOTOTRANSISTOR - LED_ON, "
      "E2E = M2M + G2G, motion = GY_OFF - GY_ON\n" +
      table.render();
  text += "the latency limits (> ms) apply to M2M, G2G and E2E, not to the motions' durations\n";
  for (const auto& r : results)
    for (const auto& note : full_loop_notes(r)) text += note + "\n";
  for (const auto& r : results) {
    if (!r.from_chains) continue;
    std::string counts;
    for (const auto& [reason, count] : r.incomplete)
      if (count > 0) counts += fmt::format("{}{} {}", counts.empty() ? "" : ", ", count, reason);
    text += fmt::format("{}: incomplete chains: {}\n", r.scenario, counts.empty() ? "none" : counts);
  }
  return text;
}

nlohmann::json full_loop_json(std::span<const FullLoopResult> results) {
  auto out = nlohmann::json::array();
  for (const auto& r : results) {
    nlohmann::json quantities = nlohmann::json::object();
    for (const auto q : analysis::kLoopQuantities) {
      const auto* s = r.find(q);
      if (s == nullptr) continue;
      nlohmann::json excluded = nlohmann::json::object();
      for (std::size_t k = 0; k < analysis::kLoopExclusions; ++k)
        excluded[std::string(analysis::key(static_cast<LoopExclusion>(k)))] = s->excluded[k];
      quantities[std::string(analysis::key(q))] = {{"summary", summary_json(s->summary)},
                                                   {"excluded", excluded}};
    }
    out.push_back(
        {{"scenario", r.scenario},
         {"file", r.file},
         {"format", r.from_chains ? std::string("chains") : std::string(formats::to_string(r.format))},
         {"events", r.events},
         {"quantities", quantities},
         {"notes", full_loop_notes(r)}});
    if (r.from_chains) {
      nlohmann::json incomplete = nlohmann::json::object();
      for (const auto& [reason, count] : r.incomplete) incomplete[reason] = count;
      out.back()["incomplete_chains"] = incomplete;
    }
  }
  return out;
}

std::vector<BoxData> full_loop_boxes(std::span<const FullLoopResult> results) {
  std::vector<BoxData> boxes;
  for (const auto& r : results)
    for (const auto q : {LoopQuantity::m2m, LoopQuantity::g2g, LoopQuantity::e2e}) {
      const auto* s = r.find(q);
      if (s == nullptr) continue;
      auto sorted = s->ns;
      std::sort(sorted.begin(), sorted.end());
      boxes.push_back(box_of(sorted, std::string(analysis::label(q)), r.scenario));
    }
  return boxes;
}

}  // namespace m2mlat::report
