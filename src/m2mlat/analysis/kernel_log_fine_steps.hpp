// Clock steps inside one level of a kernel log (kernel_log_steps.hpp), too small for the levels'
// agreement test: that test must let d move by the slewing bound between two lines (1.25 ms over
// 2.5 s at 500 ppm), so a 1 ms step hides in it. Here d is modelled instead of bounded.
//
// The model: within a level, d (detrended by its median rate: the oscillator's frequency error) is a
// local level, a random walk of variance q per second (the daemon's corrections and the crystal's
// wander), seen through white noise of variance r (the printk delay). q and r are the maximum
// likelihood pair on a grid (Student-t likelihood with 4 degrees of freedom: a late printk is no
// reason to widen the model), fitted on the level's first 4096 lines. A Kalman filter gives each
// line's innovation. A step of size S before line g adds S * rho_k to the innovations of the next
// `horizon` lines, rho_k known from the filter's gains (the filter catches up with the new level);
// its generalised likelihood ratio (Willsky & Jones) gives S's estimate, its standard deviation and
// chi2 = (S / sd)^2. The best g is a step when chi2 exceeds the Bonferroni bound for `alpha` over
// the level's lines, |S| >= min_size_ns, and a change of rate (a daemon beginning to slew: the
// other board's step taken over) explains the innovations less well. Gaps inside a stretch where d
// moves faster than half the slewing bound beyond the noise at two gaps in a row are slewing, not
// searched. The step found is taken out of d and the search repeated (at most max_steps).
// The level's floor: the size found 95 % of the time, (z + 1.645) times the median standard deviation
// of a step's estimate over the level's lines (z the bound's normal quantile).
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

namespace m2mlat::analysis {

struct FineStepOptions {
  double alpha = 1e-6;              // family-wise chance of a false step in a level without one, under the model
  std::size_t horizon = 12;         // lines after a candidate step whose innovations weigh it
  std::int64_t min_size_ns = 500'000;  // smaller level changes are not reported, ns
  double slew_ppm = 500;            // the slewing bound (kernel_log_steps.hpp), ppm
  std::size_t max_steps = 16;       // steps sought in one level at most
};

struct FineStep {
  std::size_t line = 0;      // index of the first line after the step (into the spans given)
  std::int64_t size_ns = 0;  // new - old level, ns
  std::int64_t sd_ns = 0;    // its standard deviation from the model, ns
};

struct FineSteps {
  std::vector<FineStep> steps;  // in line order
  std::int64_t floor_ns = 0;    // steps from this size on are found 95 % of the time, ns (0: too few lines)
};

// mono_ns: the lines' monotonic stamps (non-decreasing), d_ns: realtime - monotonic per line, ns;
// one level's kept lines in order.
FineSteps fine_steps(std::span<const std::int64_t> mono_ns, std::span<const std::int64_t> d_ns,
                                 const FineStepOptions& options = {});

}  // namespace m2mlat::analysis
