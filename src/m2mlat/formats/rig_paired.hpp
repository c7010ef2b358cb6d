// The reference rig's paired-results CSV: one steering event per row, both boards' timestamps and
// the latency the rig computed.
//
//   remote_station_s,remote_station_ns,vehicle_s,vehicle_ns,,m2m_latency_ms
//   1762872545,550296135,1762872546,417585462,,867.289327
//
// remote_station_* is the operator station's edge (cause) and vehicle_* the vehicle's (effect), both
// CLOCK_REALTIME seconds + nanoseconds; the fifth column has no name and is empty; m2m_latency_ms is
// a decimal with up to 6 decimals (the rig wrote between 0 and 6). Importing yields the pairs and the
// two event lists, and checks the file's own latency against vehicle - remote on every row.
#pragma once

#include <array>
#include <cstddef>
#include <ostream>
#include <span>
#include <string_view>
#include <vector>

#include "m2mlat/core/event.hpp"
#include "m2mlat/core/time.hpp"
#include "m2mlat/formats/imported.hpp"
#include "m2mlat/formats/pair_row.hpp"
#include "m2mlat/formats/pair_source.hpp"

namespace m2mlat::formats {

inline constexpr std::array<std::string_view, 6> kRigPairedColumns{
    "remote_station_s", "remote_station_ns", "vehicle_s", "vehicle_ns", "", "m2m_latency_ms"};

// How far the file's m2m_latency_ms may be from vehicle - remote and still agree: 1 us (the rig
// rounded some files to 3 decimals of ms).
inline constexpr core::Duration kRigLatencyTolerance{1'000};

// The file's own latency on one row, against the one computed from its timestamps.
struct LatencyCheck {
  long line = 0;                  // the row's line in the file
  core::Duration file_latency{};  // m2m_latency_ms exactly as written, in ns
  core::Duration difference{};    // (vehicle - remote) - file_latency
  bool agrees = true;             // |difference| <= kRigLatencyTolerance
  friend bool operator==(const LatencyCheck&, const LatencyCheck&) = default;
};

struct PairedImport {
  // pairs[i] joins causes[i] and effects[i] (cause_index = effect_index = i); clock realtime.
  std::vector<PairRow> pairs;
  std::vector<core::Event> causes;   // remote station: ImportOptions::cause (default operator/wheel)
  std::vector<core::Event> effects;  // vehicle: ImportOptions::effect (default vehicle/wheel)
  std::vector<LatencyCheck> checks;  // one per pair
  // Indices (into pairs) of the rows whose m2m_latency_ms disagrees: warnings, not errors.
  std::vector<std::size_t> disagreements;
};

// Throws core::Error(data) naming file, line and field for anything malformed. Events carry edge
// ImportOptions::edge and flags imported and no-kernel-seqno.
PairedImport import_rig_paired_csv(std::string_view text, std::string_view name,
                                   const ImportOptions& options);

// Writes pairs in the rig's layout, so that its users' scripts read m2mlat's results; the latency is
// exact with 6 decimals (core::format_ms). The cause is written as remote_station_*, the effect as
// vehicle_*, seconds rounded down and nanoseconds in [0, 10^9). The rows are read a block at a time
// (pair_source.hpp); the span overload is the same for rows held whole.
void write_rig_paired_csv(std::ostream& out, const PairSource& pairs);
void write_rig_paired_csv(std::ostream& out, std::span<const PairRow> pairs);

}  // namespace m2mlat::formats
