// The latency densities of the alignment model (formulas in alignment_model.hpp).
#include "m2mlat/pairing/alignment_model.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace m2mlat::pairing {

namespace {

double log_normal(double x, double mean, double variance) {
  const double d = x - mean;
  return -0.5 * (std::log(2 * std::numbers::pi * variance) + d * d / variance);
}

// Student's t with 4 degrees of freedom about `mean`, scale^2 = `variance`: the level's innovations
// have heavy tails (an excursion of the link: a sweep seconds late is rare, not impossible).
double log_student(double x, double mean, double variance) {
  constexpr double kNu = 4;
  const double z = (x - mean) * (x - mean) / variance;
  // log(Gamma(5/2) / (Gamma(2) sqrt(4 pi))) = log(3 sqrt(pi) / 4 / (2 sqrt(pi))) = log(3 / 8).
  return std::log(3.0 / 8.0) - 0.5 * std::log(variance) - 0.5 * (kNu + 1) * std::log1p(z / kNu);
}

double log_add(double a, double b) {
  if (a < b) std::swap(a, b);
  return b == -INFINITY ? a : a + std::log1p(std::exp(b - a));
}

}  // namespace

double log_fresh_latency(const AlignmentModel& m) {
  return std::log(m.reset) - std::log(std::max(m.max_latency_s - m.min_latency_s, 1e-9));
}

double log_level_link(const AlignmentModel& m, double latency_s, double previous_s, double dc_s) {
  dc_s = std::max(dc_s, 0.0);
  const double phi = std::exp(-dc_s / m.tau_s);
  const double mean = m.mean_s + phi * (previous_s - m.mean_s) + phi * (m.stretch - 1) * dc_s;
  const double spread = phi * m.stretch_sd * dc_s;
  return log_student(latency_s, mean,
                     m.spread_s * m.spread_s * (1 - phi * phi) + spread * spread + 2 * m.jitter_s * m.jitter_s);
}

double log_sweep_link(const AlignmentModel& m, double latency_s, double previous_s, double dc_s, double previous_stretch) {
  const double change = m.sweep_sd * std::max(dc_s, 0.0);
  return log_normal(latency_s, previous_s + (previous_stretch - 1) * dc_s, change * change + 2 * m.jitter_s * m.jitter_s);
}

double log_linked_latency(const AlignmentModel& m, double latency_s, double previous_s, double dc_s,
                          std::optional<double> previous_stretch) {
  const double level = log_level_link(m, latency_s, previous_s, dc_s);
  if (!previous_stretch) return std::log1p(-m.reset) + level;
  return std::log1p(-m.reset) + log_add(std::log(m.sweep) + log_sweep_link(m, latency_s, previous_s, dc_s, *previous_stretch),
                                        std::log1p(-m.sweep) + level);
}

double log_first_latency(const AlignmentModel& m, double latency_s) {
  const double variance = m.spread_s * m.spread_s + 2 * m.jitter_s * m.jitter_s;
  return log_add(std::log1p(-m.reset) + log_student(latency_s, m.mean_s, variance), log_fresh_latency(m));
}

}  // namespace m2mlat::pairing
