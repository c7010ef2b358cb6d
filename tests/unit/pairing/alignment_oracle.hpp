// The alignment model computed the plain way: every order-preserving one-to-one alignment of the
// candidate pairs enumerated, each scored by alignment_model.hpp's formula, summed and maximised.
// Exponential in the input: for a few edges a side only. The oracle the lattice is checked against.
#pragma once

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <map>
#include <optional>
#include <utility>
#include <vector>

#include "m2mlat/pairing/alignment_model.hpp"

namespace m2mlat::pairing::oracle {

struct OracleResult {
  double log_z = -INFINITY;
  std::map<std::pair<std::size_t, std::size_t>, double> posterior;  // candidate -> probability
  std::vector<std::pair<std::size_t, std::size_t>> best;
  double best_score = -INFINITY;
};

using Path = std::vector<std::pair<std::size_t, std::size_t>>;

// One alignment's log score by the model's formula: summed (or, for the best alignment, maximised)
// over which of its pairs were drawn afresh (z = 0) and which linked (z = 1), a two-state recursion.
inline double log_score(const std::vector<std::int64_t>& cause_ns, const std::vector<std::int64_t>& effect_ns,
                        const AlignmentModel& m, const Path& path, bool maximum = false) {
  const auto s_of = [](std::int64_t ns) { return static_cast<double>(ns) * 1e-9; };
  const auto latency = [&](std::size_t i, std::size_t j) { return s_of(effect_ns[j] - cause_ns[i]); };
  const auto add = [&](double a, double b) {
    if (maximum) return std::max(a, b);
    if (a < b) std::swap(a, b);
    return b == -INFINITY ? a : a + std::log1p(std::exp(b - a));
  };
  const double kept = std::log1p(-m.cause_loss);
  double z0 = -INFINITY, z1 = -INFINITY;
  for (std::size_t p = 0; p < path.size(); ++p) {
    const auto [i, j] = path[p];
    if (p == 0) {
      z0 = kept + log_first_latency(m, latency(i, j));
      continue;
    }
    const auto [i0, j0] = path[p - 1];
    const double afresh = add(z0, z1) + kept + log_fresh_latency(m);
    double linked = -INFINITY;
    if (i - i0 - 1 <= m.max_skip && j - j0 - 1 <= m.max_skip) {
      const double dc = s_of(cause_ns[i] - cause_ns[i0]);
      linked = z0 + log_linked_latency(m, latency(i, j), latency(i0, j0), dc, std::nullopt);
      if (p >= 2) {
        const auto [i1, j1] = path[p - 2];
        const double interval = s_of(cause_ns[i0] - cause_ns[i1]);
        const double stretch = interval > 0 ? s_of(effect_ns[j0] - effect_ns[j1]) / interval : m.stretch;
        linked = add(linked, z1 + log_linked_latency(m, latency(i, j), latency(i0, j0), dc, stretch));
      }
      linked += kept;
    }
    z0 = afresh;
    z1 = linked;
  }
  double s = path.empty() ? 0.0 : add(z0, z1);
  s += static_cast<double>(cause_ns.size() - path.size()) * std::log(m.cause_loss);
  s += static_cast<double>(effect_ns.size() - path.size()) * std::log(m.unmatched_per_s);
  return s;
}

inline OracleResult enumerate(const std::vector<std::int64_t>& cause_ns, const std::vector<std::int64_t>& effect_ns,
                              const AlignmentModel& m) {
  const std::size_t n = cause_ns.size(), k = effect_ns.size();
  const auto in_window = [&](std::size_t i, std::size_t j) {
    const std::int64_t d = effect_ns[j] - cause_ns[i];
    return d >= std::llround(m.min_latency_s * 1e9) && d <= std::llround(m.max_latency_s * 1e9);
  };
  struct Scored {
    Path path;
    double sum, max;  // summed and maximised over the pairs drawn afresh
  };
  std::vector<Scored> paths;  // every alignment with its scores
  Path path;
  const auto extend = [&](auto&& self, std::size_t from_i, std::size_t from_j) -> void {
    paths.push_back({path, log_score(cause_ns, effect_ns, m, path), log_score(cause_ns, effect_ns, m, path, true)});
    for (std::size_t i = from_i; i < n; ++i)
      for (std::size_t j = from_j; j < k; ++j)
        if (in_window(i, j)) {
          path.emplace_back(i, j);
          self(self, i + 1, j + 1);
          path.pop_back();
        }
  };
  extend(extend, 0, 0);
  OracleResult out;
  double peak = -INFINITY;
  for (const auto& p : paths) peak = std::max(peak, p.sum);
  double sum = 0;
  for (const auto& p : paths) sum += std::exp(p.sum - peak);
  out.log_z = peak + std::log(sum);
  for (const auto& p : paths) {
    for (const auto& pair : p.path) out.posterior[pair] += std::exp(p.sum - out.log_z);
    if (p.max > out.best_score) out.best_score = p.max, out.best = p.path;
  }
  return out;
}

}  // namespace m2mlat::pairing::oracle
