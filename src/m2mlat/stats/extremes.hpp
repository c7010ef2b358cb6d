// The smallest and largest sample, with the identity of the sample that holds each.
//
// A report that says "max 1.84 s" should also say which pair it was, so that the raw events
// behind an outlier can be found. Samples carry an optional parallel id (a pair index or a store
// sequence number); without ids, a sample's id is its index in the input.
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>

namespace m2mlat::stats {

struct Extreme {
  std::int64_t ns = 0;    // the sample's value, exact (ns)
  std::int64_t id = 0;    // ids[index] when ids were given, else index
  std::size_t index = 0;  // position of the sample in the input
  double ms() const { return static_cast<double>(ns) / 1e6; }
  friend bool operator==(const Extreme&, const Extreme&) = default;
};

struct Extremes {
  Extreme min;
  Extreme max;
};

// Ties go to the earliest sample in input order (as numpy.argmin and argmax do). nullopt for an
// empty sample. `ids` is empty or holds one id per value; anything else throws core::Error(internal).
std::optional<Extremes> find_extremes(std::span<const std::int64_t> values_ns,
                                      std::span<const std::int64_t> ids = {});

}  // namespace m2mlat::stats
