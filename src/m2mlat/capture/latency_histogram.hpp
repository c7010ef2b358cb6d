// A fixed-size histogram of durations (ns) for quantiles of a stream too long to keep: the
// recorder's edge -> durable commit latency over a run of any length. Log-linear buckets: exact
// below 32 ns, then 32 buckets per power of two, so a quantile is reported at most 1/32 (about 3 %)
// above the true value; 16 KiB, no allocation after construction.
#pragma once

#include <array>
#include <cstdint>

namespace m2mlat::capture {

class LatencyHistogram {
 public:
  void add(std::int64_t ns);  // negative values (a clock stepped back) count as 0
  std::uint64_t count() const { return count_; }
  std::int64_t max() const { return max_; }
  // The q-quantile, 0 <= q <= 1 (nearest rank), as the upper end of its bucket, never above max();
  // 0 when empty.
  std::int64_t quantile(double q) const;

 private:
  static constexpr int kSubBits = 5;  // 32 buckets per power of two
  static constexpr int kSub = 1 << kSubBits;
  static int index(std::uint64_t ns);
  static std::int64_t upper(int index);
  std::array<std::uint64_t, 64 * kSub> counts_{};
  std::uint64_t count_ = 0;
  std::int64_t max_ = 0;
};

}  // namespace m2mlat::capture
