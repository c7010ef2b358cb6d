// The alignment model computed the plain way: every order-preserving one-to-one alignment of the
// candidate pairs enumerated, each scored by alignment_model.hpp's formula, summed and maximised.
// Exponential in the input: for a few edges a side only. The oracle the lattice is checked against.
#pragma once

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <map>
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

// One alignment's log score, by the model's formula.
inline double log_score(const std::vector<std::int64_t>& cause_ns, const std::vector<std::int64_t>& effect_ns,
                        const AlignmentModel& m, const Path& path) {
  const auto latency = [&](std::size_t i, std::size_t j) { return static_cast<double>(effect_ns[j] - cause_ns[i]) * 1e-9; };
  double s = 0;
  for (std::size_t p = 0; p < path.size(); ++p) {
    const auto [i, j] = path[p];
    s += std::log1p(-m.cause_loss);
    if (p == 0) {
      s += log_first_latency(m, latency(i, j));
    } else {
      const auto [i0, j0] = path[p - 1];
      const bool linked = i - i0 - 1 <= m.max_skip && j - j0 - 1 <= m.max_skip;
      const double dc = static_cast<double>(cause_ns[i] - cause_ns[i0]) * 1e-9;
      s += linked ? log_linked_latency(m, latency(i, j), latency(i0, j0), dc) : log_fresh_latency(m);
    }
  }
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
  std::vector<std::pair<Path, double>> paths;  // every alignment with its score
  Path path;
  const auto extend = [&](auto&& self, std::size_t from_i, std::size_t from_j) -> void {
    paths.emplace_back(path, log_score(cause_ns, effect_ns, m, path));
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
  for (const auto& [p, s] : paths) peak = std::max(peak, s);
  double sum = 0;
  for (const auto& [p, s] : paths) sum += std::exp(s - peak);
  out.log_z = peak + std::log(sum);
  for (const auto& [p, s] : paths) {
    for (const auto& pair : p) out.posterior[pair] += std::exp(s - out.log_z);
    if (s > out.best_score) out.best_score = s, out.best = p;
  }
  return out;
}

}  // namespace m2mlat::pairing::oracle
