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

double log_add(double a, double b) {
  if (a < b) std::swap(a, b);
  return b == -INFINITY ? a : a + std::log1p(std::exp(b - a));
}

}  // namespace

double log_fresh_latency(const AlignmentModel& m) {
  return std::log(m.reset) - std::log(std::max(m.max_latency_s - m.min_latency_s, 1e-9));
}

double log_link_only(const AlignmentModel& m, double latency_s, double previous_s, double dc_s) {
  const double phi = std::exp(-std::max(dc_s, 0.0) / m.tau_s);
  const double mean = m.mean_s + phi * (previous_s - m.mean_s) + phi * (m.stretch - 1) * dc_s;
  const double sweep = phi * m.stretch_sd * dc_s;
  const double variance = m.spread_s * m.spread_s * (1 - phi * phi) + sweep * sweep + 2 * m.jitter_s * m.jitter_s;
  return std::log1p(-m.reset) + log_normal(latency_s, mean, variance);
}

double log_linked_latency(const AlignmentModel& m, double latency_s, double previous_s, double dc_s) {
  return log_add(log_link_only(m, latency_s, previous_s, dc_s), log_fresh_latency(m));
}

double log_first_latency(const AlignmentModel& m, double latency_s) {
  const double variance = m.spread_s * m.spread_s + 2 * m.jitter_s * m.jitter_s;
  return log_add(std::log1p(-m.reset) + log_normal(latency_s, m.mean_s, variance), log_fresh_latency(m));
}

}  // namespace m2mlat::pairing
