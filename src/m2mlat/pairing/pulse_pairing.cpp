// Mutual-nearest pairing of pulse edges (rule in pulse_pairing.hpp).
#include "m2mlat/pairing/pulse_pairing.hpp"

#include <algorithm>
#include <numeric>

#include "m2mlat/core/error.hpp"

namespace m2mlat::pairing {

namespace {

// Positions of t in time order (stable).
std::vector<std::size_t> time_order(std::span<const std::int64_t> t) {
  std::vector<std::size_t> order(t.size());
  std::iota(order.begin(), order.end(), std::size_t{0});
  std::stable_sort(order.begin(), order.end(), [&](auto x, auto y) { return t[x] < t[y]; });
  return order;
}

// For each of `from` (sorted values), the index into `to` (sorted values) of the nearest value; ties
// go to the earlier one. `to` must not be empty.
std::vector<std::size_t> nearest(const std::vector<std::int64_t>& from, const std::vector<std::int64_t>& to) {
  std::vector<std::size_t> out(from.size());
  std::size_t j = 0;  // the last value of `to` at or before from[i] (or 0): never goes back
  for (std::size_t i = 0; i < from.size(); ++i) {
    while (j + 1 < to.size() && to[j + 1] <= from[i]) ++j;
    const auto distance = [&](std::size_t k) { return to[k] > from[i] ? to[k] - from[i] : from[i] - to[k]; };
    out[i] = j + 1 < to.size() && distance(j + 1) < distance(j) ? j + 1 : j;
  }
  return out;
}

}  // namespace

core::Duration median_interval(std::span<const std::int64_t> t_ns) {
  if (t_ns.size() < 2) return core::Duration{0};
  std::vector<std::int64_t> sorted(t_ns.begin(), t_ns.end());
  std::sort(sorted.begin(), sorted.end());
  std::vector<std::int64_t> gaps;
  gaps.reserve(sorted.size() - 1);
  for (std::size_t i = 1; i < sorted.size(); ++i) gaps.push_back(sorted[i] - sorted[i - 1]);
  const auto mid = gaps.begin() + static_cast<std::ptrdiff_t>(gaps.size() / 2);
  std::nth_element(gaps.begin(), mid, gaps.end());
  return core::Duration{*mid};
}

PulsePairing pair_pulses(std::span<const std::int64_t> a_ns, std::span<const std::int64_t> b_ns,
                         const PulsePairingOptions& options) {
  PulsePairing result;
  if (options.period.count() < 0)
    throw core::Error(core::ErrorKind::usage, "pulse pairing: the period must not be negative");
  result.period = options.period.count() > 0 ? options.period : median_interval(a_ns);
  if (result.period.count() <= 0)
    throw core::Error(core::ErrorKind::usage,
                      "pulse pairing: cannot estimate the pulse period from fewer than 2 edges on the first "
                      "board (give the period)");
  const auto order_a = time_order(a_ns);
  const auto order_b = time_order(b_ns);
  std::vector<std::int64_t> a, b;  // sorted; A shifted by the expected offset
  a.reserve(order_a.size());
  b.reserve(order_b.size());
  for (auto k : order_a) a.push_back(a_ns[k] + options.expected_offset.count());
  for (auto k : order_b) b.push_back(b_ns[k]);

  std::vector<bool> used_b(b.size(), false);
  if (!a.empty() && !b.empty()) {
    const auto a_to_b = nearest(a, b);
    const auto b_to_a = nearest(b, a);
    // Strictly less than half a period: an edge exactly between two pulses belongs to neither.
    const std::int64_t limit = (result.period.count() + 1) / 2;
    for (std::size_t i = 0; i < a.size(); ++i) {
      const std::size_t j = a_to_b[i];
      const std::int64_t distance = b[j] > a[i] ? b[j] - a[i] : a[i] - b[j];
      if (b_to_a[j] != i || distance >= limit) {
        result.unmatched_a.push_back(order_a[i]);
        continue;
      }
      used_b[j] = true;
      result.pairs.push_back({order_a[i], order_b[j], a_ns[order_a[i]], b_ns[order_b[j]]});
    }
  } else {
    result.unmatched_a = order_a;
  }
  for (std::size_t j = 0; j < b.size(); ++j)
    if (!used_b[j]) result.unmatched_b.push_back(order_b[j]);
  return result;
}

}  // namespace m2mlat::pairing
