// The reference rig's synchronisation-test CSV: one shared pulse (wired to both boards every
// 500 ms) per row, with the offset between the two boards' timestamps of it.
//
//   trigger_time_s,sync_offset_ns,Jitter_ns,,sync_offset_ms,Jitter_ms
//   1.065,-922880,-256,,0.92288,0.000256
//
// trigger_time_s: decimal seconds since the test started; sync_offset_ns: the difference of the two
// boards' CLOCK_REALTIME stamps of the pulse, integer ns; Jitter_ns: the change of the offset since
// the previous row, integer ns. The rig parsed its timestamps through double, so its offsets are
// multiples of 256 ns: they are kept exactly as written. The two ms columns repeat the magnitudes
// (and the first row's Jitter_ms is 0 where Jitter_ns is not): they are checked to be decimals but
// not used.
#pragma once

#include <array>
#include <cstdint>
#include <string_view>
#include <vector>

#include "m2mlat/core/time.hpp"

namespace m2mlat::formats {

inline constexpr std::array<std::string_view, 6> kRigSyncColumns{
    "trigger_time_s", "sync_offset_ns", "Jitter_ns", "", "sync_offset_ms", "Jitter_ms"};

struct SyncSample {
  long line = 0;                  // the row's line in the file
  core::Duration trigger_time{};  // since the start of the test (trigger_time_s, exact)
  std::int64_t offset_ns = 0;     // sync_offset_ns as written
  std::int64_t jitter_ns = 0;     // Jitter_ns as written
  friend bool operator==(const SyncSample&, const SyncSample&) = default;
};

struct SyncImport {
  std::vector<SyncSample> samples;  // in file order
};

// Throws core::Error(data) naming file, line and field for anything malformed.
SyncImport import_rig_sync_csv(std::string_view text, std::string_view name);

}  // namespace m2mlat::formats
