// Refractory filter against contact bounce: after an edge is kept, further edges on the same side
// within `period` are bounces. A Hall sensor (or a mechanical switch) can fire a few extra edges within
// a few ms of the true one; the first edge is the one whose timestamp is the motion's.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "m2mlat/core/time.hpp"

namespace m2mlat::pairing {

struct RefractoryResult {
  std::vector<std::int64_t> kept;     // indices into the input of the edges kept
  std::vector<std::int64_t> bounces;  // indices into the input of the edges suppressed
};

// `times_ns` must be sorted ascending (one clock). period <= 0 keeps everything.
// The period is measured from the last KEPT edge, so a long burst of bounces cannot extend itself.
RefractoryResult refractory_filter(std::span<const std::int64_t> times_ns, core::Duration period);

// The same rule, returning only the bounces (ascending input indices): every other edge is kept.
// The matcher's form: on 10^7 edges it saves the 80 MB list of kept indices.
std::vector<std::int64_t> refractory_bounces(std::span<const std::int64_t> times_ns, core::Duration period);

// Input index of each kept edge, for kept positions visited in increasing order: the k-th kept edge
// is input edge k + (the number of bounces before it). O(1) amortised per step, no table.
class KeptIndex {
 public:
  explicit KeptIndex(std::span<const std::int64_t> bounces) : bounces_(bounces) {}
  // `kept_position` must not decrease from one call to the next.
  std::int64_t operator()(std::size_t kept_position) {
    auto index = static_cast<std::int64_t>(kept_position + skipped_);
    while (skipped_ < bounces_.size() && bounces_[skipped_] <= index) ++skipped_, ++index;
    return index;
  }

 private:
  std::span<const std::int64_t> bounces_;
  std::size_t skipped_ = 0;
};

}  // namespace m2mlat::pairing
