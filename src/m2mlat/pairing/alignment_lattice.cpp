// Forward-backward and Viterbi over the candidate lattice (alignment_lattice.hpp), in log space.
// A running sum over earlier pairs is kept as (value, stamp): the value valid at a cause index
// (stamp), brought to another by cause_loss per cause between.
#include "m2mlat/pairing/alignment_lattice.hpp"

#include <algorithm>
#include <cmath>

namespace m2mlat::pairing {

namespace {

// A log-space accumulator: a sum (log-add) or a maximum with the index it came from.
struct Acc {
  double v = -INFINITY;
  std::int64_t arg = -1;
};

Acc combine(Acc a, Acc b, bool maximum) {
  if (maximum) return b.v > a.v ? b : a;
  if (a.v < b.v) std::swap(a, b);
  if (b.v == -INFINITY) return a;
  return {a.v + std::log1p(std::exp(b.v - a.v)), a.arg};
}

double clamp_chance(double p) { return std::clamp(p, 1e-12, 1 - 1e-12); }

}  // namespace

AlignmentLattice::AlignmentLattice(std::span<const std::int64_t> cause_ns, std::span<const std::int64_t> effect_ns,
                                   const AlignmentModel& model)
    : model_(model) {
  model_.cause_loss = clamp_chance(model_.cause_loss);
  model_.reset = clamp_chance(model_.reset);
  model_.unmatched_per_s = std::max(model_.unmatched_per_s, 1e-12);
  const std::int64_t origin = std::min(cause_ns.empty() ? 0 : cause_ns.front(), effect_ns.empty() ? 0 : effect_ns.front());
  for (const auto t : cause_ns) cause_s_.push_back(static_cast<double>(t - origin) * 1e-9);
  for (const auto t : effect_ns) effect_s_.push_back(static_cast<double>(t - origin) * 1e-9);
  const auto min_ns = static_cast<std::int64_t>(std::llround(model_.min_latency_s * 1e9));
  const auto max_ns = static_cast<std::int64_t>(std::llround(model_.max_latency_s * 1e9));
  std::size_t lo = 0, hi = 0, total = 0;
  for (const auto c : cause_ns) {
    while (lo < effect_ns.size() && effect_ns[lo] - c < min_ns) ++lo;
    hi = std::max(hi, lo);
    while (hi < effect_ns.size() && effect_ns[hi] - c <= max_ns) ++hi;
    lo_.push_back(lo);
    hi_.push_back(hi);
    offset_.push_back(total);
    total += hi - lo;
  }
  latency_.resize(total);
  for (std::size_t i = 0; i < lo_.size(); ++i)
    for (std::size_t j = lo_[i]; j < hi_[i]; ++j) latency_[index(i, j)] = effect_s_[j] - cause_s_[i];
  forward(false);
  backward();
  forward(true);
}

double AlignmentLattice::posterior(std::size_t cause, std::size_t effect) const {
  if (cause >= lo_.size() || effect < lo_[cause] || effect >= hi_[cause]) return 0;
  const auto k = index(cause, effect);
  return std::exp(alpha_[k] + beta_[k] - log_z_);
}

void AlignmentLattice::forward(bool maximum) {
  const std::size_t n = lo_.size(), m = effect_s_.size();
  const double log_loss = std::log(model_.cause_loss), log_kept = std::log1p(-model_.cause_loss);
  const double log_unmatched = std::log(model_.unmatched_per_s), fresh = log_fresh_latency(model_);
  const std::size_t skip = model_.max_skip;
  auto& out = maximum ? viterbi_ : alpha_;
  out.assign(latency_.size(), -INFINITY);
  if (maximum) back_.assign(latency_.size(), -1);
  // Per effect column: the pairs ending there of causes before the stamp, each brought forward.
  std::vector<Acc> column(m);
  std::vector<std::int64_t> stamp(m, 0);
  const auto column_at = [&](std::size_t j, std::size_t i) {
    Acc a = column[j];
    if (a.v != -INFINITY) a.v += static_cast<double>(static_cast<std::int64_t>(i) - stamp[j]) * log_loss;
    return a;
  };
  Acc behind;  // the columns before `folded`, at stamp behind_stamp
  std::int64_t behind_stamp = 0;
  std::size_t folded = 0;
  for (std::size_t i = 0; i < n; ++i) {
    if (behind.v != -INFINITY) behind.v += static_cast<double>(static_cast<std::int64_t>(i) - behind_stamp) * log_loss;
    behind_stamp = static_cast<std::int64_t>(i);
    for (; folded < lo_[i]; ++folded) {
      Acc shifted = behind;
      shifted.v += log_unmatched;
      behind = combine(shifted, column_at(folded, i), maximum);
    }
    Acc earlier = behind;  // every pair before cause i and before effect j, brought to (i, j)
    for (std::size_t j = lo_[i]; j < hi_[i]; ++j) {
      if (j > lo_[i]) {
        earlier.v += log_unmatched;
        earlier = combine(earlier, column_at(j - 1, i), maximum);
      }
      const double latency = latency_[index(i, j)];
      Acc best{static_cast<double>(i) * log_loss + static_cast<double>(j) * log_unmatched +
                   log_first_latency(model_, latency),
               -1};
      best = combine(best, {fresh + earlier.v, earlier.arg}, maximum);
      for (std::size_t i2 = i >= skip + 1 ? i - skip - 1 : 0; i2 < i; ++i2) {
        const double causes_between = static_cast<double>(i - 1 - i2) * log_loss;
        const std::size_t from = std::max(lo_[i2], j >= skip + 1 ? j - skip - 1 : 0);
        for (std::size_t j2 = from; j2 < std::min(hi_[i2], j); ++j2) {
          const auto k2 = index(i2, j2);
          // A sum takes the fresh draw with every predecessor (`earlier`); a maximum needs it per path.
          const double dc = cause_s_[i] - cause_s_[i2];
          const double v = out[k2] + causes_between + static_cast<double>(j - 1 - j2) * log_unmatched +
                           (maximum ? log_linked_latency(model_, latency, latency_[k2], dc)
                                    : log_link_only(model_, latency, latency_[k2], dc));
          best = combine(best, {v, static_cast<std::int64_t>(k2)}, maximum);
        }
      }
      const auto k = index(i, j);
      out[k] = log_kept + best.v;
      if (maximum) back_[k] = best.arg;
    }
    for (std::size_t j = lo_[i]; j < hi_[i]; ++j) {
      Acc now = column_at(j, i);
      now.v += log_loss;
      column[j] = combine(now, {out[index(i, j)], static_cast<std::int64_t>(index(i, j))}, maximum);
      stamp[j] = static_cast<std::int64_t>(i) + 1;
    }
  }
  // The end: the causes and effects after the last pair unmatched (or no pair at all).
  Acc end{static_cast<double>(n) * log_loss + static_cast<double>(m) * log_unmatched, -1};
  for (std::size_t i = 0; i < n; ++i)
    for (std::size_t j = lo_[i]; j < hi_[i]; ++j) {
      const auto k = index(i, j);
      end = combine(end,
                    {out[k] + static_cast<double>(n - 1 - i) * log_loss + static_cast<double>(m - 1 - j) * log_unmatched,
                     static_cast<std::int64_t>(k)},
                    maximum);
    }
  if (!maximum) {
    log_z_ = end.v;
    return;
  }
  best_ = {};
  best_.log_score = end.v;
  for (std::int64_t k = end.arg; k >= 0; k = back_[static_cast<std::size_t>(k)]) {
    const auto idx = static_cast<std::size_t>(k);
    const auto i = static_cast<std::size_t>(std::upper_bound(offset_.begin(), offset_.end(), idx) - offset_.begin()) - 1;
    best_.pairs.emplace_back(i, lo_[i] + (idx - offset_[i]));
    best_.probability.push_back(std::exp(alpha_[idx] + beta_[idx] - log_z_));
  }
  std::reverse(best_.pairs.begin(), best_.pairs.end());
  std::reverse(best_.probability.begin(), best_.probability.end());
}

void AlignmentLattice::backward() {
  const std::size_t n = lo_.size(), m = effect_s_.size();
  const double log_loss = std::log(model_.cause_loss), log_kept = std::log1p(-model_.cause_loss);
  const double log_unmatched = std::log(model_.unmatched_per_s), fresh = log_fresh_latency(model_);
  const std::size_t skip = model_.max_skip;
  beta_.assign(latency_.size(), -INFINITY);
  // Per effect column: the later pairs starting there (their pair's factor and what follows), each
  // brought back to the stamp by cause_loss per cause between.
  std::vector<double> column(m, -INFINITY);
  std::vector<std::int64_t> stamp(m, static_cast<std::int64_t>(n) - 1);
  const auto column_at = [&](std::size_t j, std::size_t i) {
    double v = column[j];
    if (v != -INFINITY) v += static_cast<double>(stamp[j] - static_cast<std::int64_t>(i)) * log_loss;
    return v;
  };
  const auto add = [](double a, double b) {
    if (a < b) std::swap(a, b);
    return b == -INFINITY ? a : a + std::log1p(std::exp(b - a));
  };
  double ahead = -INFINITY;  // the columns from `unfolded` on, at stamp ahead_stamp
  std::int64_t ahead_stamp = static_cast<std::int64_t>(n) - 1;
  std::size_t unfolded = m;
  for (std::size_t i = n; i-- > 0;) {
    if (ahead != -INFINITY) ahead += static_cast<double>(ahead_stamp - static_cast<std::int64_t>(i)) * log_loss;
    ahead_stamp = static_cast<std::int64_t>(i);
    for (; unfolded > hi_[i]; --unfolded) ahead = add(ahead + log_unmatched, column_at(unfolded - 1, i));
    double later = ahead;  // every pair after cause i and after effect j, brought to (i, j)
    for (std::size_t j = hi_[i]; j-- > lo_[i];) {
      if (j + 1 < hi_[i]) later = add(later + log_unmatched, column_at(j + 1, i));
      const double latency = latency_[index(i, j)];
      double total = static_cast<double>(n - 1 - i) * log_loss + static_cast<double>(m - 1 - j) * log_unmatched;
      total = add(total, fresh + later);
      for (std::size_t i2 = i + 1; i2 < std::min(n, i + skip + 2); ++i2) {
        const double causes_between = static_cast<double>(i2 - i - 1) * log_loss;
        for (std::size_t j2 = std::max(lo_[i2], j + 1); j2 < std::min(hi_[i2], j + skip + 2); ++j2) {
          const auto k2 = index(i2, j2);
          total = add(total, causes_between + static_cast<double>(j2 - j - 1) * log_unmatched + log_kept +
                                 log_link_only(model_, latency_[k2], latency, cause_s_[i2] - cause_s_[i]) + beta_[k2]);
        }
      }
      beta_[index(i, j)] = total;
    }
    for (std::size_t j = lo_[i]; j < hi_[i]; ++j) {
      column[j] = add(column_at(j, i) + log_loss, log_kept + beta_[index(i, j)]);
      stamp[j] = static_cast<std::int64_t>(i) - 1;
    }
  }
}

}  // namespace m2mlat::pairing
