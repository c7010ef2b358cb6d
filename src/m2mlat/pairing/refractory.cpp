// Refractory filter: one pass, keeps the first edge of every burst closer than the period.
#include "m2mlat/pairing/refractory.hpp"

namespace m2mlat::pairing {

RefractoryResult refractory_filter(std::span<const std::int64_t> times_ns, core::Duration period) {
  RefractoryResult result;
  result.kept.reserve(times_ns.size());
  const std::int64_t period_ns = period.count();
  bool have_kept = false;
  std::int64_t last_kept_ns = 0;
  for (std::size_t i = 0; i < times_ns.size(); ++i) {
    const auto index = static_cast<std::int64_t>(i);
    if (have_kept && period_ns > 0 && times_ns[i] - last_kept_ns < period_ns) {
      result.bounces.push_back(index);
      continue;
    }
    result.kept.push_back(index);
    last_kept_ns = times_ns[i];
    have_kept = true;
  }
  return result;
}

}  // namespace m2mlat::pairing
