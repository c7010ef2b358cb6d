// The median and IQR with and without the flagged pairs, against the quantiles of the two samples built.
#include "m2mlat/analysis/flagged_effect.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <vector>

#include "m2mlat/stats/quantile.hpp"
#include "m2mlat/stats/rng.hpp"

using namespace m2mlat;

namespace {
double median_ms(std::vector<std::int64_t> v) { return stats::median(std::move(v)) / 1e6; }
double iqr_ms(std::vector<std::int64_t> v) {
  std::sort(v.begin(), v.end());
  const std::span<const std::int64_t> s(v);
  return (stats::quantile(s, 0.75) - stats::quantile(s, 0.25)) / 1e6;
}
}  // namespace

TEST(FlaggedEffect, KthValueOfTheSampleWithOrWithoutOthersIsThatOfTheSampleBuilt) {
  stats::Rng rng(3);
  for (int trial = 0; trial < 200; ++trial) {
    std::vector<std::int64_t> kept(1 + rng.below(40)), others(1 + rng.below(10));
    for (auto& x : kept) x = static_cast<std::int64_t>(rng.below(50)) - 25;  // ties and negatives
    for (auto& x : others) x = static_cast<std::int64_t>(rng.below(50)) - 25;
    std::sort(kept.begin(), kept.end());
    std::sort(others.begin(), others.end());
    auto together = kept;
    together.insert(together.end(), others.begin(), others.end());
    std::sort(together.begin(), together.end());
    for (std::size_t k = 0; k < together.size(); ++k) ASSERT_EQ(analysis::kth_value(kept, others, true, k), together[k]);
    // Taking `others` out of `together` leaves `kept`.
    for (std::size_t k = 0; k < kept.size(); ++k) ASSERT_EQ(analysis::kth_value(together, others, false, k), kept[k]);
  }
}

TEST(FlaggedEffect, MedianAndIqrWithAndWithoutTheFlaggedPairs) {
  std::vector<std::int64_t> kept, flagged;
  for (int i = 0; i < 101; ++i) kept.push_back(900'000'000 + i * 1'000'000);
  for (int i = 0; i < 30; ++i) flagged.push_back(1'500'000'000 + i * 3'000'000);
  std::sort(kept.begin(), kept.end());
  auto all = kept;
  all.insert(all.end(), flagged.begin(), flagged.end());
  std::sort(all.begin(), all.end());

  stats::MedianIqrCi ci;
  ci.median_ms = {940, 960};  // half width 10 ms
  ci.iqr_ms = {40, 60};
  const auto out = analysis::flagged_effect(kept, flagged, false, ci);
  ASSERT_TRUE(out);
  EXPECT_EQ(out->n_without, 101u);
  EXPECT_EQ(out->n_with, 131u);
  EXPECT_DOUBLE_EQ(out->median_without_ms, median_ms(kept));
  EXPECT_DOUBLE_EQ(out->median_with_ms, median_ms(all));
  EXPECT_DOUBLE_EQ(out->iqr_with_ms, iqr_ms(all));
  EXPECT_TRUE(out->median_moves());  // 950 -> 965 ms
  // The same from the other side: statistics with the flagged pairs (--include-ambiguous).
  const auto in = analysis::flagged_effect(all, flagged, true, ci);
  ASSERT_TRUE(in);
  EXPECT_DOUBLE_EQ(in->median_without_ms, out->median_without_ms);
  EXPECT_DOUBLE_EQ(in->iqr_without_ms, out->iqr_without_ms);
  EXPECT_DOUBLE_EQ(in->median_with_ms, out->median_with_ms);
  EXPECT_FALSE(analysis::flagged_effect(kept, {}, false, ci));
  EXPECT_FALSE(analysis::flagged_effect(kept, flagged, false, std::nullopt)->median_moves());  // no CI, no verdict
}
