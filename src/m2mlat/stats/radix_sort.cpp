// The radix sort of latency samples (radix_sort.hpp).
#include "m2mlat/stats/radix_sort.hpp"

#include <algorithm>
#include <array>
#include <cstring>
#include <memory>

namespace m2mlat::stats {

namespace {

// Keys compared as unsigned: flipping the sign bit puts negative latencies first, in order.
constexpr std::uint64_t kSignBit = std::uint64_t{1} << 63;

// Below this, std::sort's few compares cost less than the radix sort's 8 x 256 counters.
constexpr std::size_t kRadixFrom = 4096;

}  // namespace

void sort_ns(std::span<std::int64_t> values) {
  const std::size_t n = values.size();
  if (n < kRadixFrom) {
    std::sort(values.begin(), values.end());
    return;
  }
  // Counts of every byte value at every byte position, from one pass over the keys.
  std::array<std::array<std::size_t, 256>, 8> counts{};
  for (const std::int64_t v : values) {
    const std::uint64_t key = static_cast<std::uint64_t>(v) ^ kSignBit;
    for (std::size_t d = 0; d < 8; ++d) ++counts[d][(key >> (8 * d)) & 0xFF];
  }
  auto buffer = std::make_unique_for_overwrite<std::int64_t[]>(n);
  std::int64_t* from = values.data();
  std::int64_t* to = buffer.get();
  for (std::size_t d = 0; d < 8; ++d) {
    auto& count = counts[d];
    // A byte every key shares orders nothing: skip its pass.
    if (std::find(count.begin(), count.end(), n) != count.end()) continue;
    std::array<std::size_t, 256> start{};
    std::size_t sum = 0;
    for (std::size_t b = 0; b < 256; ++b) start[b] = sum, sum += count[b];
    const unsigned shift = static_cast<unsigned>(8 * d);
    for (std::size_t i = 0; i < n; ++i) {
      const std::uint64_t key = static_cast<std::uint64_t>(from[i]) ^ kSignBit;
      to[start[(key >> shift) & 0xFF]++] = from[i];
    }
    std::swap(from, to);
  }
  if (from != values.data()) std::memcpy(values.data(), from, n * sizeof(std::int64_t));
}

}  // namespace m2mlat::stats
