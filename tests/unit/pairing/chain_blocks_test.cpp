// The matcher's back-pointers block by block (ChainBlocks): chains that meet are written out at their
// meeting point and their blocks given back, chains that never meet keep every block, and the pass's
// result is the chain it ends with, whichever way its pairs were written.
#include "m2mlat/pairing/chain_blocks.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <vector>

using namespace m2mlat::pairing;

namespace {

constexpr std::size_t kBlock = ChainBlocks::kBlockCauses;

// A pass over `causes` causes with two candidates each: candidate 2i pairs cause i with effect i,
// candidate 2i + 1 with effect i + 1 (window start i, offsets 0 and 1). pred_of(id) gives each
// candidate's predecessor. After every block the ends of both chains through the last cause are
// handed over, as the alignment hands over its live chain ends; held_after collects held().
struct TwoWayPass {
  std::size_t causes;
  std::uint32_t (*pred_of)(std::uint32_t id);
  std::vector<std::size_t> held_after;

  std::vector<std::uint32_t> run(ChainBlocks& chains, std::uint32_t last) {
    chains.start(causes, true);
    ChainBlocks::Rows rows{};
    std::uint32_t next = 0;
    for (std::size_t i = 0; i < causes; ++i) {
      if (i % kBlock == 0) {
        if (i > 0) {
          chains.close(next);
          const std::vector<std::uint32_t> ends{next - 2, next - 1};
          chains.settle(ends);
          held_after.push_back(chains.held());
        }
        rows = chains.open(i, next, 2 * std::min(kBlock, causes - i));
      }
      const std::size_t row = i % kBlock;
      rows.row_start[row] = next;
      rows.row_lo[row] = static_cast<std::uint32_t>(i);
      for (std::uint8_t offset = 0; offset < 2; ++offset, ++next) {
        rows.offset[next - rows.row_start[0]] = offset;
        rows.pred[next - rows.row_start[0]] = pred_of(next);
      }
    }
    chains.close(next);
    return chains.finish(last);
  }
};

TEST(ChainBlocks, ChainsThatMeetAreWrittenOutAndTheirBlocksGivenBack) {
  // Both candidates of a cause continue the chain of effects i - 1: the two chains through the last
  // cause meet at its predecessor's first candidate.
  TwoWayPass pass{
      3 * kBlock + 5, [](std::uint32_t id) { return id < 2 ? kNoCandidate : (id / 2 - 1) * 2; }, {}};
  ChainBlocks chains;
  const auto last = static_cast<std::uint32_t>(2 * pass.causes - 1);  // the last cause with effect i + 1
  const auto match = pass.run(chains, last);
  ASSERT_EQ(pass.held_after.size(), 3u);
  // The meeting point is in the block just closed: only that block is held.
  for (const auto held : pass.held_after) EXPECT_EQ(held, 2 * kBlock);
  ASSERT_EQ(match.size(), pass.causes);
  for (std::size_t i = 0; i + 1 < pass.causes; ++i) ASSERT_EQ(match[i], i) << "cause " << i;
  EXPECT_EQ(match.back(), pass.causes);
  EXPECT_EQ(chains.held(), 0u);
}

TEST(ChainBlocks, ChainsThatNeverMeetKeepEveryBlock) {
  // Two chains side by side from the first cause on: effect i all along, or effect i + 1 all along.
  TwoWayPass pass{2 * kBlock + 7, [](std::uint32_t id) { return id < 2 ? kNoCandidate : id - 2; }, {}};
  ChainBlocks chains;
  const auto match = pass.run(chains, static_cast<std::uint32_t>(2 * pass.causes - 1));
  ASSERT_EQ(pass.held_after.size(), 2u);
  EXPECT_EQ(pass.held_after[0], 2 * kBlock);
  EXPECT_EQ(pass.held_after[1], 4 * kBlock);
  for (std::size_t i = 0; i < pass.causes; ++i) ASSERT_EQ(match[i], i + 1) << "cause " << i;
}

TEST(ChainBlocks, AChainThatSkipsCausesLeavesThemUnmatched) {
  // Each candidate continues the one of the same offset two causes back: four chains that never
  // meet; the pass ends with the even causes' chain of offset 0, and the odd causes stay unmatched.
  TwoWayPass pass{kBlock + 3, [](std::uint32_t id) { return id < 4 ? kNoCandidate : id - 4; }, {}};
  ChainBlocks chains;
  const auto even_last = static_cast<std::uint32_t>(pass.causes - 1) & ~1u;  // the last even cause
  const auto match = pass.run(chains, 2 * even_last);
  for (std::size_t i = 0; i < pass.causes; ++i)
    ASSERT_EQ(match[i], i % 2 == 0 ? i : kNoCandidate) << "cause " << i;
}

TEST(ChainBlocks, WideWindowsKeepTheEffectIndex) {
  ChainBlocks chains;
  chains.start(3, false);
  auto rows = chains.open(0, 0, 3);
  const std::uint32_t effects[] = {700, 90'000, 1'000'000};
  for (std::uint32_t i = 0; i < 3; ++i) {
    rows.row_start[i] = i;
    rows.row_lo[i] = 0;
    rows.effect[i] = effects[i];
    rows.pred[i] = i == 0 ? kNoCandidate : i - 1;
  }
  chains.close(3);
  const auto match = chains.finish(2);
  EXPECT_EQ(match, (std::vector<std::uint32_t>{700, 90'000, 1'000'000}));
}

}  // namespace
