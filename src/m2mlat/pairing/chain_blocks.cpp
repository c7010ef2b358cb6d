// Back-pointers of an alignment pass, block by block, given back once settled (see chain_blocks.hpp).
#include "m2mlat/pairing/chain_blocks.hpp"

#include <algorithm>
#include <utility>

namespace m2mlat::pairing {

namespace {
// Blocks kept for reuse: where the chains meet in the block just written, the one before it is given
// back as each block is opened, so two spares serve a whole pass.
constexpr std::size_t kSpareBlocks = 2;
}  // namespace

void ChainBlocks::start(std::size_t causes, bool narrow) {
  blocks_.clear();  // empty unless a pass before ended without finish()
  match_.assign(causes, kNoCandidate);
  settled_ = kNoCandidate;
  causes_ = causes;
  narrow_ = narrow;
  credit_ = 0;
}

ChainBlocks::Rows ChainBlocks::open(std::size_t first_cause, std::uint32_t first_id, std::size_t capacity) {
  Block b;
  if (!spare_.empty()) {
    b = std::move(spare_.back());
    spare_.pop_back();
  }
  if (!b.pred || b.capacity < capacity || b.narrow != narrow_) {
    // A quarter more than asked: the next blocks, of about the same size, then reuse it as it is.
    b.capacity = capacity + capacity / 4;
    b.narrow = narrow_;
    b.pred = std::make_unique_for_overwrite<std::uint32_t[]>(b.capacity);
    b.offset.reset(), b.effect.reset();
    if (narrow_)
      b.offset = std::make_unique_for_overwrite<std::uint8_t[]>(b.capacity);
    else
      b.effect = std::make_unique_for_overwrite<std::uint32_t[]>(b.capacity);
  }
  if (!b.row_start) {
    b.row_start = std::make_unique_for_overwrite<std::uint32_t[]>(kBlockCauses + 1);
    b.row_lo = std::make_unique_for_overwrite<std::uint32_t[]>(kBlockCauses);
  }
  b.first_cause = first_cause;
  b.causes = std::min(kBlockCauses, causes_ - first_cause);
  b.first_id = b.end_id = first_id;
  blocks_.push_back(std::move(b));
  const Block& added = blocks_.back();
  return {added.pred.get(), added.offset.get(), added.effect.get(), added.row_start.get(), added.row_lo.get()};
}

void ChainBlocks::close(std::uint32_t end_id) {
  Block& b = blocks_.back();
  b.end_id = end_id;
  b.row_start[b.causes] = end_id;
}

// The block holding candidate `id`; `hint` is where the last search ended (ids asked for only decrease).
const ChainBlocks::Block& ChainBlocks::block_of(std::uint32_t id, std::size_t& hint) const {
  while (blocks_[hint].first_id > id) --hint;
  return blocks_[hint];
}

void ChainBlocks::settle(std::span<const std::uint32_t> ends) {
  credit_ += blocks_.back().end_id - blocks_.back().first_id;
  if (ends.empty() || credit_ <= 0) return;
  // The chains walked back together, latest candidate first (a max-heap of their current candidates):
  // chains that meet become one entry, and where one entry is left it is the meeting point.
  heap_.assign(ends.begin(), ends.end());
  std::make_heap(heap_.begin(), heap_.end());
  std::size_t hint = blocks_.size() - 1;
  std::uint32_t meeting = kNoCandidate;
  for (;;) {
    std::pop_heap(heap_.begin(), heap_.end());
    const std::uint32_t latest = heap_.back();
    heap_.pop_back();
    while (!heap_.empty() && heap_.front() == latest) {
      std::pop_heap(heap_.begin(), heap_.end());
      heap_.pop_back();
    }
    if (heap_.empty()) {
      meeting = latest;
      break;
    }
    // Every live chain goes through the settled candidate, so the others cannot lie before it.
    if (latest == settled_) return;
    const std::uint32_t before = pred(latest, hint);
    --credit_;
    if (before == kNoCandidate) return;  // a chain's first pair, the others elsewhere: no meeting yet
    heap_.push_back(before);
    std::push_heap(heap_.begin(), heap_.end());
  }
  write_chain(meeting);
  settled_ = meeting;
  while (!blocks_.empty() && blocks_.front().end_id <= meeting + std::uint64_t{1}) {
    if (spare_.size() < kSpareBlocks) spare_.push_back(std::move(blocks_.front()));
    blocks_.pop_front();
  }
}

void ChainBlocks::write_chain(std::uint32_t from) {
  std::size_t hint = blocks_.size() - 1;
  const Block* b = nullptr;
  std::size_t row = 0;
  for (std::uint32_t c = from; c != settled_;) {
    const Block& in = block_of(c, hint);
    if (&in != b) b = &in, row = in.causes;
    while (b->row_start[row] > c) --row;  // the cause: row_start[row] <= c < row_start[row + 1]
    const std::uint32_t k = c - b->first_id;
    match_[b->first_cause + row] = narrow_ ? b->row_lo[row] + b->offset[k] : b->effect[k];
    c = b->pred[k];
  }
}

std::vector<std::uint32_t> ChainBlocks::finish(std::uint32_t last) {
  if (last != kNoCandidate) write_chain(last);
  settled_ = last;
  while (!blocks_.empty()) {
    if (spare_.size() < kSpareBlocks) spare_.push_back(std::move(blocks_.front()));
    blocks_.pop_front();
  }
  return std::move(match_);
}

std::size_t ChainBlocks::held() const {
  std::size_t n = 0;
  for (const auto& b : blocks_) n += b.end_id - b.first_id;
  return n;
}

}  // namespace m2mlat::pairing
