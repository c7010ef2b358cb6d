// The full loop from the full-loop rig's files: per event, motion-to-motion (M2M = vehicle onset -
// station onset), glass-to-glass (G2G = photo edge - LED on), end-to-end (E2E = M2M + G2G) and each
// side's motion duration (GY_OFF - GY_ON), then the usual summary of each (stats::summarize).
//
// Every difference is taken in int64 ns (an overflow is an exclusion, not a wrap); doubles appear
// only in the summaries. An event lacking a value a quantity needs, or whose value is impossible (an
// OFF before its ON, a negative G2G), has no value of that quantity and is counted by reason: the
// counts are shown beside the statistics, nothing is dropped silently. A negative M2M is not
// impossible (two boards' onset detectors: the rig's own baseline has negative ones) and is kept;
// E2E has a value only where M2M and G2G both have one, else it takes M2M's reason, then G2G's.
// The camera-to-monitor file gives G2G alone.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "m2mlat/formats/camera_latency.hpp"
#include "m2mlat/formats/format.hpp"
#include "m2mlat/formats/full_loop_csv.hpp"
#include "m2mlat/stats/summary.hpp"

namespace m2mlat::analysis {

enum class LoopQuantity : std::uint8_t { m2m, g2g, e2e, vehicle_motion, station_motion };
inline constexpr std::array<LoopQuantity, 5> kLoopQuantities{LoopQuantity::m2m, LoopQuantity::g2g,
                                                             LoopQuantity::e2e, LoopQuantity::vehicle_motion,
                                                             LoopQuantity::station_motion};
// "M2M", "G2G", "E2E", "vehicle motion", "station motion": for people.
std::string_view label(LoopQuantity quantity);
// "m2m", "g2g", "e2e", "vehicle_motion", "station_motion": JSON members, CSV values, file names.
std::string_view key(LoopQuantity quantity);

// M2M, G2G and E2E are latencies; the motions are durations, to which no latency threshold applies.
constexpr bool is_latency(LoopQuantity quantity) {
  return quantity == LoopQuantity::m2m || quantity == LoopQuantity::g2g || quantity == LoopQuantity::e2e;
}
// The summary options of one quantity: `options` without thresholds for a motion.
stats::SummaryOptions options_for(LoopQuantity quantity, const stats::SummaryOptions& options);

// Why an event has no value of a quantity.
enum class LoopExclusion : std::uint8_t {
  missing,     // a timestamp it needs is empty in the file
  impossible,  // an OFF before its ON, or a negative G2G
  overflow,    // the difference (or sum) does not fit in int64 ns
};
inline constexpr std::size_t kLoopExclusions = 3;
std::string_view key(LoopExclusion exclusion);  // "missing", "impossible", "overflow"

// One quantity of one event: its value in ns, or why it has none.
struct LoopValue {
  std::optional<std::int64_t> ns;
  LoopExclusion why = LoopExclusion::missing;  // meaningful when ns is unset
  friend bool operator==(const LoopValue&, const LoopValue&) = default;
};

// The five quantities of one row, indexed by LoopQuantity.
std::array<LoopValue, kLoopQuantities.size()> loop_values(const formats::FullLoopRow& row);

// One quantity over a file: the values that exist (file order), the line of each (the sample ids of
// the summary's extremes), the exclusions by reason, and the summary of the values.
struct LoopSeries {
  std::vector<std::int64_t> ns;
  std::vector<std::int64_t> lines;
  std::array<std::size_t, kLoopExclusions> excluded{};  // by LoopExclusion
  stats::Summary summary;
  std::size_t excluded_total() const { return excluded[0] + excluded[1] + excluded[2]; }
};

struct FullLoopResult {
  std::string scenario;  // the file's stem, like every data-file scenario
  std::string file;      // the path as given
  formats::Format format = formats::Format::full_loop_csv;
  std::size_t events = 0;  // rows (full-loop CSV) or latencies (camera file) read
  // By LoopQuantity; the camera file has only G2G.
  std::array<std::optional<LoopSeries>, kLoopQuantities.size()> quantities;
  // Built from raw traces and LED/photo edges as chains (analysis/chains.hpp) rather than read from a
  // file: `format` does not apply, and the incomplete chains are counted here by reason (key, count).
  bool from_chains = false;
  std::vector<std::pair<std::string, std::size_t>> incomplete;
  const LoopSeries* find(LoopQuantity quantity) const {
    const auto& q = quantities.at(static_cast<std::size_t>(quantity));
    return q ? &*q : nullptr;
  }
};

FullLoopResult analyse_full_loop(std::string scenario, std::string file, const formats::FullLoopImport& rows,
                                 const stats::SummaryOptions& options);
FullLoopResult analyse_camera_latency(std::string scenario, std::string file,
                                      const formats::CameraLatencyImport& latencies,
                                      const stats::SummaryOptions& options);

// Takes the full-loop files (full-loop CSV, camera-to-monitor) out of `inputs` (stores and other data
// files stay, in their order) and analyses them, in the order given. `format` as --format: when it
// is one of the two, every input is taken; when it is another, none. Standard input ("-") is taken
// only when --format names it. Throws core::Error naming file and line for a malformed file.
std::vector<FullLoopResult> take_full_loop_files(std::vector<std::string>& inputs,
                                                 std::optional<formats::Format> format,
                                                 const stats::SummaryOptions& options);

}  // namespace m2mlat::analysis
