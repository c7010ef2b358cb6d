// Offline merge through Store::ingest (see merge.hpp).
#include "m2mlat/store/merge.hpp"

#include <fmt/format.h>

#include <algorithm>

#include "m2mlat/core/error.hpp"

namespace m2mlat::store {

MergeResult merge_store(store::Store& campaign, const std::string& board_path, std::size_t chunk) {
  store::Options read;
  read.read_only = true;
  const auto board = store::Store::open(board_path, read);
  MergeResult result;
  result.path = board_path;
  result.origin = board.store_id();
  if (result.origin == campaign.store_id())
    throw core::Error(core::ErrorKind::usage,
                      fmt::format("{}: is the campaign store itself ({})", board_path, campaign.path()));

  // The chunked reads below select by seq and join sessions: a row breaking the schema's rules (a
  // file edited by another tool) would be left out without a word. Refuse the file instead.
  board.check_rows();

  store::IngestBatch batch;
  batch.origin = result.origin;
  batch.sessions = board.sessions();  // few; given with every chunk, so each chunk stands alone
  for (const auto& s : batch.sessions)
    if (std::find(result.nodes.begin(), result.nodes.end(), s.node) == result.nodes.end())
      result.nodes.push_back(s.node);

  // A rate block holds up to 4096 samples (72 KiB): far fewer of them per chunk than events keeps a
  // chunk's memory near that of `chunk` events.
  const std::size_t block_chunk = std::max<std::size_t>(1, chunk / 256);
  store::IngestCursor cursor = campaign.ingest_cursor(result.origin);
  for (;;) {
    batch.events = board.events_after(cursor.events, chunk);
    batch.clock_samples = board.clock_samples_after(cursor.clock_samples, chunk);
    batch.losses = board.losses_after(cursor.losses, chunk);
    batch.rate_blocks = board.rate_blocks_after(cursor.rate_blocks, block_chunk);
    batch.markers = board.markers_after(cursor.markers, chunk);
    const bool last = batch.events.size() < chunk && batch.clock_samples.size() < chunk &&
                      batch.losses.size() < chunk && batch.rate_blocks.size() < block_chunk &&
                      batch.markers.size() < chunk;
    const store::IngestCursor next = campaign.ingest(batch);
    result.events += static_cast<std::int64_t>(batch.events.size());
    result.clock_samples += static_cast<std::int64_t>(batch.clock_samples.size());
    result.losses += static_cast<std::int64_t>(batch.losses.size());
    result.rate_blocks += static_cast<std::int64_t>(batch.rate_blocks.size());
    result.markers += static_cast<std::int64_t>(batch.markers.size());
    cursor = next;
    if (last) break;
  }
  return result;
}

}  // namespace m2mlat::store
