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

std::uint64_t key_of(std::int64_t v) { return static_cast<std::uint64_t>(v) ^ kSignBit; }
std::size_t digit(std::int64_t v, unsigned byte) { return (key_of(v) >> (8 * byte)) & 0xFF; }

using ByteCounts = std::array<std::array<std::size_t, 256>, 8>;  // [byte position][byte value]

ByteCounts count_bytes(std::span<const std::int64_t> values, unsigned bytes) {
  ByteCounts counts{};
  for (const std::int64_t v : values) {
    const std::uint64_t key = key_of(v);
    for (unsigned d = 0; d < bytes; ++d) ++counts[d][(key >> (8 * d)) & 0xFF];
  }
  return counts;
}

// A byte every key shares orders nothing: its pass is skipped.
bool shared(const std::array<std::size_t, 256>& count, std::size_t n) {
  return std::find(count.begin(), count.end(), n) != count.end();
}

// Least-significant-digit passes over the low `bytes` bytes, through `buffer` (at least as long).
void sort_low_bytes(std::span<std::int64_t> values, unsigned bytes, std::int64_t* buffer) {
  const std::size_t n = values.size();
  if (n < kRadixFrom) {
    std::sort(values.begin(), values.end());
    return;
  }
  const ByteCounts counts = count_bytes(values, bytes);
  std::int64_t* from = values.data();
  std::int64_t* to = buffer;
  for (unsigned d = 0; d < bytes; ++d) {
    if (shared(counts[d], n)) continue;
    std::array<std::size_t, 256> start{};
    std::size_t sum = 0;
    for (std::size_t b = 0; b < 256; ++b) start[b] = sum, sum += counts[d][b];
    for (std::size_t i = 0; i < n; ++i) to[start[digit(from[i], d)]++] = from[i];
    std::swap(from, to);
  }
  if (from != values.data()) std::memcpy(values.data(), from, n * sizeof(std::int64_t));
}

}  // namespace

void sort_ns(std::span<std::int64_t> values) {
  const std::size_t n = values.size();
  if (n < kRadixFrom) {
    std::sort(values.begin(), values.end());
    return;
  }
  // The highest byte the keys do not all share: the bytes above it order nothing.
  const ByteCounts counts = count_bytes(values, 8);
  unsigned top = 8;
  while (top > 0 && shared(counts[top - 1], n)) --top;
  if (top == 0) return;  // every key equal
  const unsigned d = top - 1;
  // In place by that byte (each key swapped straight into its bucket), so that the passes over the
  // lower bytes need a buffer of the largest bucket only, not of every key: latencies of a few
  // seconds spread over ~100 buckets of 16.7 ms, and 10^7 of them were 80 MB more at the peak.
  std::array<std::size_t, 256> next{}, end{};
  std::size_t sum = 0, largest = 0;
  for (std::size_t b = 0; b < 256; ++b) {
    next[b] = sum;
    sum += counts[d][b];
    end[b] = sum;
    largest = std::max(largest, counts[d][b]);
  }
  for (std::size_t b = 0; b < 256; ++b) {
    while (next[b] < end[b]) {
      std::int64_t v = values[next[b]];
      for (std::size_t k = digit(v, d); k != b; k = digit(v, d)) std::swap(v, values[next[k]++]);
      values[next[b]++] = v;
    }
  }
  if (d == 0) return;
  const auto buffer = std::make_unique_for_overwrite<std::int64_t[]>(largest);
  std::size_t first = 0;
  for (std::size_t b = 0; b < 256; ++b) {
    const std::size_t count = counts[d][b];
    sort_low_bytes(values.subspan(first, count), d, buffer.get());
    first += count;
  }
}

}  // namespace m2mlat::stats
