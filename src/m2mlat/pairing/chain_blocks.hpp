// The back-pointers of one alignment pass of the matcher (matcher.cpp, align), kept block by block and
// given back as soon as the chains they hold are settled, the way a Viterbi decoder keeps its survivor
// paths: memory follows the stretch of the recording in which the best chain is still undecided, not
// the recording.
//
// A pass writes, cause after cause, every allowed candidate pair with the candidate its best chain
// continues (its predecessor, or kNoCandidate: a chain's first pair). Candidates are numbered in cause
// order. Between blocks of causes the pass hands over the ends of every chain that a later cause can
// still extend; where all of them go back through one candidate, the chain up to it is final whatever
// comes later: its pairs are written to the result, and the blocks holding only earlier candidates are
// given back. Where the chains do not meet (at the start, or in a long stall with two ways to pair it),
// the blocks stay until they do, as the whole pass did before.
#pragma once

#include <cstddef>
#include <cstdint>
#include <deque>
#include <limits>
#include <memory>
#include <span>
#include <vector>

namespace m2mlat::pairing {

inline constexpr std::uint32_t kNoCandidate = std::numeric_limits<std::uint32_t>::max();

class ChainBlocks {
 public:
  // Causes per block: large enough that the search for the chains' meeting point (a few hundred steps
  // where they meet within a few causes) is a small part of a block's work, small enough that a block
  // (~12 candidates a cause at 5 bytes, and 8 bytes a cause) stays below a MiB.
  static constexpr std::size_t kBlockCauses = 4096;

  // Where a block's candidates and rows are written. The effect of a candidate is `offset` (its
  // distance from its cause's window start, row_lo) in a narrow pass, else `effect` (its index).
  struct Rows {
    std::uint32_t* pred;
    std::uint8_t* offset;      // narrow passes
    std::uint32_t* effect;     // wide passes
    std::uint32_t* row_start;  // per cause of the block: its first candidate's number
    std::uint32_t* row_lo;     // per cause of the block: its window's first effect
  };

  // Starts a pass over `causes` causes; `narrow`: every window holds at most 256 effects. Every cause
  // of the result is unmatched until a chain through it is settled.
  void start(std::size_t causes, bool narrow);
  // Opens the block of causes from `first_cause` (a multiple of kBlockCauses), its first candidate
  // numbered `first_id`, with room for `capacity` candidates. Blocks given back are reused.
  Rows open(std::size_t first_cause, std::uint32_t first_id, std::size_t capacity);
  // Closes the open block: `end_id` is the number of the next candidate.
  void close(std::uint32_t end_id);
  // After a closed block: `ends` are the last candidates of every chain a later cause can extend
  // (none kNoCandidate; empty while a chain may still start afresh: then nothing settles). Settles
  // their common ancestor, if they have one, and gives back the blocks before it. The search walks the
  // chains back from their ends; a search is put off while the steps of those before exceed the
  // candidates written, so that over a pass the steps exceed them by one search's at most.
  void settle(std::span<const std::uint32_t> ends);
  // The pass's result: the chain ending at `last` (kNoCandidate: none beyond the settled part) written
  // out; per cause its effect, or kNoCandidate. Ends the pass.
  std::vector<std::uint32_t> finish(std::uint32_t last);

  // Candidates held in the blocks not given back (for the tests: what the memory follows).
  std::size_t held() const;

 private:
  struct Block {
    std::size_t first_cause = 0, causes = 0, capacity = 0;
    std::uint32_t first_id = 0, end_id = 0;
    bool narrow = false;
    std::unique_ptr<std::uint32_t[]> pred, effect, row_start, row_lo;
    std::unique_ptr<std::uint8_t[]> offset;
  };
  const Block& block_of(std::uint32_t id, std::size_t& hint) const;
  std::uint32_t pred(std::uint32_t id, std::size_t& hint) const {
    const Block& b = block_of(id, hint);
    return b.pred[id - b.first_id];
  }
  // Writes the chain from `from` back to the settled candidate (excluded) into the result.
  void write_chain(std::uint32_t from);

  std::deque<Block> blocks_;  // in cause order; the last is the open one while a block is written
  std::vector<Block> spare_;  // given back, kept for the next blocks: their pages are touched once
  std::vector<std::uint32_t> match_;
  std::uint32_t settled_ = kNoCandidate;  // the last settled candidate: every live chain goes through it
  std::size_t causes_ = 0;
  bool narrow_ = false;
  std::int64_t credit_ = 0;  // candidates written minus the search's steps
  std::vector<std::uint32_t> heap_;
};

}  // namespace m2mlat::pairing
