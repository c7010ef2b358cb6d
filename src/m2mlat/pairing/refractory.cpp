// Refractory filter: one pass, keeps the first edge of every burst closer than the period.
#include "m2mlat/pairing/refractory.hpp"

namespace m2mlat::pairing {

std::vector<std::int64_t> refractory_bounces(std::span<const std::int64_t> times_ns, core::Duration period) {
  std::vector<std::int64_t> bounces;
  const std::int64_t period_ns = period.count();
  if (period_ns <= 0 || times_ns.empty()) return bounces;
  std::int64_t last_kept_ns = times_ns[0];
  for (std::size_t i = 1; i < times_ns.size(); ++i) {
    if (times_ns[i] - last_kept_ns < period_ns)
      bounces.push_back(static_cast<std::int64_t>(i));
    else
      last_kept_ns = times_ns[i];
  }
  return bounces;
}

RefractoryResult refractory_filter(std::span<const std::int64_t> times_ns, core::Duration period) {
  RefractoryResult result;
  result.bounces = refractory_bounces(times_ns, period);
  result.kept.reserve(times_ns.size() - result.bounces.size());
  KeptIndex index(result.bounces);
  for (std::size_t k = 0; k < times_ns.size() - result.bounces.size(); ++k) result.kept.push_back(index(k));
  return result;
}

}  // namespace m2mlat::pairing
