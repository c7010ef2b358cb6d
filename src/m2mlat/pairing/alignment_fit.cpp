// Viterbi training of the alignment model (alignment_fit.hpp).
#include "m2mlat/pairing/alignment_fit.hpp"

#include <algorithm>
#include <cmath>
#include <functional>
#include <optional>
#include <vector>

namespace m2mlat::pairing {

namespace {

double median(std::vector<double> v) {
  const auto mid = v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2);
  std::nth_element(v.begin(), mid, v.end());
  return *mid;
}

// The densest 50 ms of every candidate latency: its centre, s.
double densest_latency(std::span<const std::int64_t> cause_ns, std::span<const std::int64_t> effect_ns,
                       const AlignmentFitOptions& o) {
  std::vector<double> latencies;
  std::size_t lo = 0;
  for (const auto c : cause_ns) {
    while (lo < effect_ns.size() && static_cast<double>(effect_ns[lo] - c) * 1e-9 < o.min_latency_s) ++lo;
    for (std::size_t j = lo; j < effect_ns.size() && static_cast<double>(effect_ns[j] - c) * 1e-9 <= o.max_latency_s; ++j)
      latencies.push_back(static_cast<double>(effect_ns[j] - c) * 1e-9);
  }
  if (latencies.empty()) return (o.min_latency_s + o.max_latency_s) / 2;
  std::sort(latencies.begin(), latencies.end());
  std::size_t best = 0, best_count = 0;
  for (std::size_t a = 0, b = 0; a < latencies.size(); ++a) {
    while (b < latencies.size() && latencies[b] - latencies[a] <= 0.05) ++b;
    if (b - a > best_count) best_count = b - a, best = a;
  }
  return latencies[best] + 0.025;
}

// The log score of consecutive pairs under a model, summed over which were drawn afresh (the
// two-state recursion of alignment_model.hpp); the causes and effects left unmatched aside.
double path_likelihood(const AlignmentModel& m, std::span<const std::pair<std::size_t, std::size_t>> pairs,
                       std::span<const std::int64_t> cause_ns, std::span<const std::int64_t> effect_ns) {
  const auto s_of = [](std::int64_t ns) { return static_cast<double>(ns) * 1e-9; };
  const auto latency = [&](std::size_t k) { return s_of(effect_ns[pairs[k].second] - cause_ns[pairs[k].first]); };
  const auto add = [](double a, double b) {
    if (a < b) std::swap(a, b);
    return b == -INFINITY ? a : a + std::log1p(std::exp(b - a));
  };
  double z0 = log_first_latency(m, latency(0)), z1 = -INFINITY;
  for (std::size_t k = 1; k < pairs.size(); ++k) {
    const auto [i, j] = pairs[k];
    const auto [i0, j0] = pairs[k - 1];
    const double afresh = add(z0, z1) + log_fresh_latency(m);
    double linked = -INFINITY;
    if (i - i0 - 1 <= m.max_skip && j - j0 - 1 <= m.max_skip) {
      const double dc = s_of(cause_ns[i] - cause_ns[i0]);
      linked = z0 + log_linked_latency(m, latency(k), latency(k - 1), dc, std::nullopt);
      if (k >= 2) {
        const auto [i1, j1] = pairs[k - 2];
        const double interval = s_of(cause_ns[i0] - cause_ns[i1]);
        const double stretch = interval > 0 ? s_of(effect_ns[j0] - effect_ns[j1]) / interval : m.stretch;
        linked = add(linked, z1 + log_linked_latency(m, latency(k), latency(k - 1), dc, stretch));
      }
    }
    z0 = afresh;
    z1 = linked;
  }
  return add(z0, z1);
}

// The largest value of f over a logarithmic grid of `steps` points from lo to hi, then refined
// around it by a factor of sqrt(ratio) twice.
double search(const std::function<double(double)>& f, double lo, double hi, int steps) {
  const double ratio = std::pow(hi / lo, 1.0 / (steps - 1));
  double best = lo, best_value = -INFINITY;
  for (int k = 0; k < steps; ++k) {
    const double x = lo * std::pow(ratio, k);
    const double v = f(x);
    if (v > best_value) best_value = v, best = x;
  }
  for (double r = std::sqrt(ratio); r > 1.0001; r = std::sqrt(r)) {
    for (const double x : {best / r, best * r}) {
      const double v = f(x);
      if (v > best_value) best_value = v, best = x;
    }
  }
  return best;
}

}  // namespace

namespace {

// Viterbi training (the rounds of alignment_fit.hpp) from out.model on; then the alignment with its
// probabilities.
void train(std::span<const std::int64_t> cause_ns, std::span<const std::int64_t> effect_ns, int max_iterations,
           FittedAlignment& out) {
  auto& m = out.model;
  const double span_s = cause_ns.empty() || effect_ns.empty()
                            ? 1.0
                            : std::max(1.0, static_cast<double>(std::max(cause_ns.back(), effect_ns.back()) -
                                                                std::min(cause_ns.front(), effect_ns.front())) * 1e-9);
  out.alignment = {};
  for (int iteration = 1;; ++iteration) {
    AlignmentLattice lattice(cause_ns, effect_ns, m, false);
    const auto& best = lattice.best();
    const bool same = iteration > 1 && best.pairs == out.alignment.pairs;
    out.alignment = best;
    out.iterations += 1;
    if (same || iteration >= max_iterations || best.pairs.empty()) {
      // The last round's parameters made this alignment: now with its probabilities.
      out.alignment = AlignmentLattice(cause_ns, effect_ns, m).best();
      return;
    }
    // Re-estimate from the alignment.
    const auto& pairs = best.pairs;
    const auto p = static_cast<double>(pairs.size());
    m.cause_loss = std::clamp((static_cast<double>(cause_ns.size()) - p + 0.5) / (static_cast<double>(cause_ns.size()) + 1), 1e-4, 0.5);
    m.unmatched_per_s = std::max((static_cast<double>(effect_ns.size()) - p + 0.5) / span_s, 1e-6);
    std::vector<double> latencies;
    for (const auto& [i, j] : pairs) latencies.push_back(static_cast<double>(effect_ns[j] - cause_ns[i]) * 1e-9);
    m.mean_s = median(latencies);
    std::vector<double> deviations;
    for (const double l : latencies) deviations.push_back(std::fabs(l - m.mean_s));
    m.spread_s = std::max(1.4826 * median(deviations), 0.001);
    // The pairs' own likelihood, on at most the first 4000 of them (the parameters are the log's:
    // more pairs move them little and cost the search in proportion).
    const std::span<const std::pair<std::size_t, std::size_t>> sample(pairs.data(), std::min<std::size_t>(pairs.size(), 4000));
    const auto likelihood = [&](const AlignmentModel& trial) { return path_likelihood(trial, sample, cause_ns, effect_ns); };
    // One pass over the parameters a round (the rounds repeat it).
    const auto set = [&](double AlignmentModel::*field, double lo, double hi) {
      m.*field = search([&](double x) { AlignmentModel t = m; t.*field = x; return likelihood(t); }, lo, hi, 17);
    };
    set(&AlignmentModel::jitter_s, 1e-4, 0.3);
    set(&AlignmentModel::stretch, 0.3, 4);
    set(&AlignmentModel::stretch_sd, 0.003, 2);
    set(&AlignmentModel::tau_s, 0.3, 3000);
    set(&AlignmentModel::reset, 1e-5, 0.5);
    set(&AlignmentModel::sweep, 0.01, 0.99);
    set(&AlignmentModel::sweep_sd, 0.002, 1);
  }
}

}  // namespace

FittedAlignment fit_alignment(std::span<const std::int64_t> cause_ns, std::span<const std::int64_t> effect_ns,
                              const AlignmentFitOptions& options) {
  FittedAlignment out;
  auto& m = out.model;
  m.min_latency_s = options.min_latency_s;
  m.max_latency_s = options.max_latency_s;
  m.max_skip = options.max_skip;
  const double span_s = cause_ns.empty() || effect_ns.empty()
                            ? 1.0
                            : std::max(1.0, static_cast<double>(std::max(cause_ns.back(), effect_ns.back()) -
                                                                std::min(cause_ns.front(), effect_ns.front())) * 1e-9);
  m.mean_s = densest_latency(cause_ns, effect_ns, options);
  m.spread_s = 0.2;
  m.cause_loss = 0.05;
  m.unmatched_per_s = std::max(0.05 * static_cast<double>(effect_ns.size()) / span_s, 1e-6);
  m.reset = 0.05;
  m.tau_s = 30;
  m.stretch = 1;
  m.stretch_sd = 0.3;
  m.jitter_s = 0.005;
  train(cause_ns, effect_ns, options.max_iterations, out);
  return out;
}

}  // namespace m2mlat::pairing
