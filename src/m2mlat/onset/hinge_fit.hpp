// The least-squares hinge fit behind the flank detector: a signal p(t) that is at a rest level c0
// (fitted) on one side of t0 and on the other rises from it as c1 tau (a torque step) or as c2 tau^2 + c3
// tau^3 + c4 tau^4 (a smooth start), c1, c2 >= 0, tau the time away from t0; the better of the two shapes is
// kept. t0 is found by a coarse then ever finer scans over the sample times, then a parabola through the best
// three. Its standard uncertainty: the half-width of the t0 interval whose residual sum of squares stays
// within one residual variance of the best, widened by sqrt((1 + rho) / (1 - rho)) for the lag-1
// correlation rho of the samples on the rest side.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>

namespace m2mlat::onset {

struct HingeFit {
  std::int64_t t0_ns = 0;  // the hinge, ns (on the samples' clock)
  double sd_ns = 0;        // standard uncertainty of t0 from the fit, ns
  bool valid = false;      // false: too few samples to fit
};

// times_ns (increasing) and p (same length): the window. rising = true: p = 0 before t0 and rises
// after it (an onset); false: p falls to 0 at t0 and stays there (an end).
HingeFit fit_hinge(std::span<const std::int64_t> times_ns, std::span<const double> p, bool rising);

}  // namespace m2mlat::onset
