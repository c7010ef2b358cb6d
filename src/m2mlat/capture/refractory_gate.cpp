// One comparison per edge.
#include "m2mlat/capture/refractory_gate.hpp"

namespace m2mlat::capture {

bool RefractoryGate::admit(core::TimePoint time) {
  if (period_.count() > 0 && last_kept_ && last_kept_->clock() == time.clock() &&
      time - *last_kept_ < period_) {
    ++suppressed_;
    return false;
  }
  last_kept_ = time;
  return true;
}

}  // namespace m2mlat::capture
