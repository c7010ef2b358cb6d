// The latency sort gives std::sort's sequence: negative, equal, wide and narrow keys, below and
// above the size where it switches from std::sort (for all the keys, and for one bucket of them).
#include "m2mlat/stats/radix_sort.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <limits>
#include <random>
#include <vector>

namespace m2mlat::stats {
namespace {

TEST(SortNs, TheSameSequenceAsStdSort) {
  std::mt19937_64 rng(19);
  for (const std::size_t n : {std::size_t{0}, std::size_t{1}, std::size_t{4095}, std::size_t{4096}, std::size_t{100'000}}) {
    for (int kind = 0; kind < 6; ++kind) {
      std::vector<std::int64_t> v(n);
      for (auto& x : v) {
        const auto r = rng();
        switch (kind) {
          case 0: x = static_cast<std::int64_t>(r); break;                                 // any int64
          case 1: x = static_cast<std::int64_t>(r % 2'000'000'000) - 20'000'000; break;    // latencies, some < 0
          case 2: x = 42; break;                                                          // all equal
          case 3: x = static_cast<std::int64_t>(r % 3) == 0 ? std::numeric_limits<std::int64_t>::min()
                                                            : std::numeric_limits<std::int64_t>::max(); break;
          case 4: x = static_cast<std::int64_t>(r % 256) << 40; break;                     // one byte differs
          // A steady link: 50 ms wide, so the highest differing byte (16.7 ms) leaves buckets of
          // thousands of keys, each sorted by its lower bytes through the shared buffer.
          default: x = 900'000'000 + static_cast<std::int64_t>(r % 50'000'000); break;
        }
      }
      auto expected = v;
      std::sort(expected.begin(), expected.end());
      sort_ns(v);
      EXPECT_EQ(v, expected) << "n " << n << " kind " << kind;
    }
  }
}

}  // namespace
}  // namespace m2mlat::stats
