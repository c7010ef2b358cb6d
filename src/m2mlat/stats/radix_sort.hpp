// Sorting latency samples (int64 ns) for the statistics: a least-significant-digit radix sort.
//
// std::sort took 4 % of `m2mlat stats` on 10^6 pairs and more at 10^7 (n log n compares with a
// data-dependent branch each). The radix sort makes one pass to count the 8 byte digits of every
// key; bytes that are the same in every key are skipped (latencies of less than a few seconds differ
// only in their low 4 bytes). The highest byte left is sorted in place (each key swapped into its
// bucket), then each bucket by one stable scatter pass per lower byte through a buffer as long as the
// largest bucket, not as all the keys. The result is the same sequence std::sort gives (int64 keys:
// equal keys are indistinguishable).
#pragma once

#include <cstdint>
#include <span>

namespace m2mlat::stats {

// Sorts `values` ascending. Below a few thousand values it calls std::sort.
void sort_ns(std::span<std::int64_t> values);

}  // namespace m2mlat::stats
