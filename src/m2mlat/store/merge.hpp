// Offline merge: joining per-board store files (recorded apart, e.g. in the autonomous
// synchronisation mode where the boards share no network) into one campaign store, through the
// same exactly-once ingest the live coordinator uses, so both paths hold the same events and give
// the same pairs. Merging a store again takes only what it gained since; merging twice changes
// nothing.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "m2mlat/store/store.hpp"

namespace m2mlat::store {

struct MergeResult {
  std::string path;       // the board store
  std::string origin;     // its store_id
  std::vector<std::string> nodes;  // the nodes of its sessions, in session order, each once
  std::int64_t events = 0;         // events taken now (0 when merged before and unchanged)
  std::int64_t clock_samples = 0;
  std::int64_t losses = 0;
  std::int64_t rate_blocks = 0;    // blocks of raw rate samples taken now
  std::int64_t markers = 0;        // markers taken now
};

// Takes into `campaign` what the store at `board_path` holds beyond the campaign's cursor for it,
// in chunks of `chunk` events (and chunk / 256 raw rate blocks; each chunk one transaction, so an
// interrupted merge resumes; or all of them one, in a store::WholeWrite, as `m2mlat merge` has it). Throws
// core::Error naming the file if it is not a current m2mlat store or is the campaign itself.
MergeResult merge_store(store::Store& campaign, const std::string& board_path, std::size_t chunk = 50'000);

}  // namespace m2mlat::store
