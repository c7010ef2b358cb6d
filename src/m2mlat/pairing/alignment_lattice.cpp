// Forward-backward and Viterbi over the candidate lattice (alignment_lattice.hpp), in log space.
// A running sum over earlier pairs is kept as (value, stamp): the value valid at a cause index
// (stamp), brought to another by cause_loss per cause between.
#include "m2mlat/pairing/alignment_lattice.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace m2mlat::pairing {

namespace {

// A log-space accumulator: a sum (log-add) or a maximum with the state it came from.
struct Acc {
  double v = -INFINITY;
  std::int64_t arg = -1;
};

// Terms more than this below the larger (log) add less than 1e-17 of it: below a double's precision.
constexpr double kNegligible = -40;

Acc combine(Acc a, Acc b, bool maximum) {
  if (maximum) return b.v > a.v ? b : a;
  if (a.v < b.v) std::swap(a, b);
  if (!(b.v - a.v > kNegligible)) return a;
  return {a.v + std::log1p(std::exp(b.v - a.v)), a.arg};
}

double clamp_chance(double p) { return std::clamp(p, 1e-12, 1 - 1e-12); }

// Per effect column, the totals of the pairs ending there, brought to a stamp by `step` per stamp;
// `behind` folds the columns no later window reaches. Forward: stamps count up, columns fold from
// the left; backward: down, from the right.
class Columns {
 public:
  Columns(std::size_t m, std::int64_t stamp, double step) : value_(m), stamp_(m, stamp), step_(step) {}
  Acc at(std::size_t j, std::int64_t stamp) const { return moved(value_[j], stamp_[j], stamp); }
  // Adds a pair's total to column j at `stamp`, the column's earlier pairs moved there first.
  void add(std::size_t j, std::int64_t stamp, Acc total, bool maximum) {
    value_[j] = combine(at(j, stamp), total, maximum);
    stamp_[j] = stamp;
  }
  Acc moved(Acc a, std::int64_t from, std::int64_t to) const {
    if (a.v != -INFINITY) a.v += static_cast<double>(std::llabs(to - from)) * step_;
    return a;
  }

 private:
  std::vector<Acc> value_;
  std::vector<std::int64_t> stamp_;
  double step_;
};

}  // namespace

AlignmentLattice::AlignmentLattice(std::span<const std::int64_t> cause_ns, std::span<const std::int64_t> effect_ns,
                                   const AlignmentModel& model, bool posteriors)
    : model_(model), posteriors_(posteriors) {
  model_.cause_loss = clamp_chance(model_.cause_loss);
  model_.reset = clamp_chance(model_.reset);
  model_.sweep = clamp_chance(model_.sweep);
  model_.unmatched_per_s = std::max(model_.unmatched_per_s, 1e-12);
  log_loss_ = std::log(model_.cause_loss);
  log_kept_ = std::log1p(-model_.cause_loss);
  log_unmatched_ = std::log(model_.unmatched_per_s);
  fresh_ = log_fresh_latency(model_);
  const std::int64_t origin = std::min(cause_ns.empty() ? 0 : cause_ns.front(), effect_ns.empty() ? 0 : effect_ns.front());
  for (const auto t : cause_ns) cause_s_.push_back(static_cast<double>(t - origin) * 1e-9);
  for (const auto t : effect_ns) effect_s_.push_back(static_cast<double>(t - origin) * 1e-9);
  const auto min_ns = static_cast<std::int64_t>(std::llround(model_.min_latency_s * 1e9));
  const auto max_ns = static_cast<std::int64_t>(std::llround(model_.max_latency_s * 1e9));
  std::size_t lo = 0, hi = 0;
  for (const auto c : cause_ns) {
    while (lo < effect_ns.size() && effect_ns[lo] - c < min_ns) ++lo;
    hi = std::max(hi, lo);
    while (hi < effect_ns.size() && effect_ns[hi] - c <= max_ns) ++hi;
    lo_.push_back(lo);
    hi_.push_back(hi);
  }
  std::size_t total = 0;
  for (std::size_t i = 0; i < lo_.size(); ++i) {
    offset_.push_back(total);
    total += hi_[i] - lo_[i];
  }
  const std::size_t skip = model_.max_skip;
  pred_begin_.push_back(0);
  for (std::size_t i = 0; i < lo_.size(); ++i)
    for (std::size_t j = lo_[i]; j < hi_[i]; ++j) {
      cause_.push_back(static_cast<std::uint32_t>(i));
      effect_.push_back(static_cast<std::uint32_t>(j));
      latency_.push_back(effect_s_[j] - cause_s_[i]);
      for (std::size_t i2 = i >= skip + 1 ? i - skip - 1 : 0; i2 < i; ++i2)
        for (std::size_t j2 = std::max(lo_[i2], j >= skip + 1 ? j - skip - 1 : 0); j2 < std::min(hi_[i2], j); ++j2) {
          pred_.push_back(index(i2, j2));
          pred_owner_.push_back(latency_.size() - 1);
          pred_skip_.push_back(static_cast<double>(i - 1 - i2) * log_loss_ + static_cast<double>(j - 1 - j2) * log_unmatched_);
        }
      pred_begin_.push_back(pred_.size());
    }
  // The successors: pred_ inverted (a counting sort by predecessor).
  succ_begin_.assign(latency_.size() + 1, 0);
  for (const auto p : pred_) ++succ_begin_[p + 1];
  for (std::size_t k = 0; k < latency_.size(); ++k) succ_begin_[k + 1] += succ_begin_[k];
  succ_.resize(pred_.size());
  {
    auto fill = succ_begin_;
    for (std::size_t q = 0; q < pred_.size(); ++q) succ_[fill[pred_[q]]++] = q;
  }
  log_keep_ = std::log1p(-model_.reset);
  log_sweep_ = std::log(model_.sweep);
  log_level_ = std::log1p(-model_.sweep);
  link_level_.resize(pred_.size());
  link_dc_.resize(pred_.size());
  link_stretch_.resize(pred_.size());
  link_sweep_var_.resize(pred_.size());
  link_sweep_norm_.resize(pred_.size());
  for (std::size_t q = 0; q < pred_.size(); ++q) {
    const auto k = pred_owner_[q], p = pred_[q];
    const double dc = cause_s_[cause_[k]] - cause_s_[cause_[p]];
    link_level_[q] = log_level_link(model_, latency_[k], latency_[p], dc);
    link_dc_[q] = dc;
    // Two causes on one stamp carry the log's usual stretch on, not a division by zero.
    link_stretch_[q] = dc > 0 ? (effect_s_[effect_[k]] - effect_s_[effect_[p]]) / dc : model_.stretch;
    const double change = model_.sweep_sd * dc;
    link_sweep_var_[q] = change * change + 2 * model_.jitter_s * model_.jitter_s;
    link_sweep_norm_[q] = -0.5 * std::log(2 * std::numbers::pi * link_sweep_var_[q]);
  }
  if (posteriors) {
    forward(false);
    backward();
  } else {
    log_z_ = NAN;
  }
  forward(true);
}

double AlignmentLattice::sweep_part(std::size_t q, double carried) const {
  // log_sweep_link with the link's variance and its normalisation computed once.
  const double d = latency_[pred_owner_[q]] - latency_[pred_[q]] - (carried - 1) * link_dc_[q];
  return link_sweep_norm_[q] - 0.5 * d * d / link_sweep_var_[q];
}

double AlignmentLattice::mix(double sweep, double level) const {
  double a = log_sweep_ + sweep, b = log_level_ + level;
  if (a < b) std::swap(a, b);
  return b - a > kNegligible ? a + std::log1p(std::exp(b - a)) : a;
}

std::optional<double> AlignmentLattice::stretch(std::size_t k, std::size_t s) const {
  if (s == 0) return std::nullopt;
  return link_stretch_[pred_begin_[k] + s - 1];
}

double AlignmentLattice::start(std::size_t k) const {
  return static_cast<double>(cause_[k]) * log_loss_ + static_cast<double>(effect_[k]) * log_unmatched_ +
         log_first_latency(model_, latency_[k]);
}

double AlignmentLattice::end(std::size_t k) const {
  return static_cast<double>(lo_.size() - 1 - cause_[k]) * log_loss_ +
         static_cast<double>(effect_s_.size() - 1 - effect_[k]) * log_unmatched_;
}

double AlignmentLattice::posterior(std::size_t cause, std::size_t effect) const {
  if (!posteriors_) return NAN;
  if (cause >= lo_.size() || effect < lo_[cause] || effect >= hi_[cause]) return 0;
  const auto k = index(cause, effect);
  double sum = -INFINITY;
  for (std::size_t s = 0; s < slots(k); ++s) sum = combine({sum}, {alpha_[slot(k, s)] + beta_[slot(k, s)]}, false).v;
  return std::exp(sum - log_z_);
}

void AlignmentLattice::forward(bool maximum) {
  const std::size_t n = lo_.size(), m = effect_s_.size(), candidates = latency_.size();
  auto& out = maximum ? viterbi_ : alpha_;
  out.assign(candidates + pred_.size(), -INFINITY);
  if (maximum) back_.assign(out.size(), -1);
  std::vector<Acc> total(candidates);  // per candidate: its states' total (a maximum: the best state)
  Columns columns(m, 0, log_loss_);
  Acc behind;  // the columns before `folded`, at stamp behind_stamp
  std::int64_t behind_stamp = 0;
  std::size_t folded = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const auto now = static_cast<std::int64_t>(i);
    behind = columns.moved(behind, behind_stamp, now);
    behind_stamp = now;
    for (; folded < lo_[i]; ++folded) {
      Acc shifted = behind;
      shifted.v += log_unmatched_;
      behind = combine(shifted, columns.at(folded, now), maximum);
    }
    Acc earlier = behind;  // every pair before cause i and before effect j, brought to (i, j)
    for (std::size_t j = lo_[i]; j < hi_[i]; ++j) {
      if (j > lo_[i]) {
        earlier.v += log_unmatched_;
        earlier = combine(earlier, columns.at(j - 1, now), maximum);
      }
      const auto k = index(i, j);
      // Afresh: the first pair, or a fresh draw after any earlier pair.
      const Acc fresh = combine({start(k), -1}, {fresh_ + earlier.v, earlier.arg}, maximum);
      out[slot(k, 0)] = log_kept_ + fresh.v;
      if (maximum) back_[slot(k, 0)] = fresh.arg;
      Acc best{out[slot(k, 0)], static_cast<std::int64_t>(slot(k, 0))};
      // Linked, one state per predecessor, over the predecessor's states.
      for (std::size_t q = pred_begin_[k]; q < pred_begin_[k + 1]; ++q) {
        const auto p = pred_[q];
        // The level's part once, the sweep's per predecessor state (the stretch it carries).
        const double level = link_level_[q];
        Acc from{out[slot(p, 0)] + log_keep_ + level, static_cast<std::int64_t>(slot(p, 0))};
        for (std::size_t s = 1; s < slots(p); ++s)
          from = combine(from, {out[slot(p, s)] + log_keep_ + mix(sweep_part(q, *stretch(p, s)), level),
                                static_cast<std::int64_t>(slot(p, s))},
                         maximum);
        const auto here = slot(k, 1 + q - pred_begin_[k]);
        out[here] = log_kept_ + pred_skip_[q] + from.v;
        if (maximum) back_[here] = from.arg;
        best = combine(best, {out[here], static_cast<std::int64_t>(here)}, maximum);
      }
      total[k] = best;
    }
    for (std::size_t j = lo_[i]; j < hi_[i]; ++j) columns.add(j, now + 1, total[index(i, j)], maximum);
  }
  // The end: the causes and effects after the last pair unmatched (or no pair at all).
  Acc last{static_cast<double>(n) * log_loss_ + static_cast<double>(m) * log_unmatched_, -1};
  for (std::size_t k = 0; k < candidates; ++k) last = combine(last, {total[k].v + end(k), total[k].arg}, maximum);
  if (!maximum) {
    log_z_ = last.v;
    return;
  }
  best_ = {};
  best_.log_score = last.v;
  std::vector<std::size_t> slot_start(candidates);
  for (std::size_t k = 0; k < candidates; ++k) slot_start[k] = slot(k, 0);
  for (std::int64_t st = last.arg; st >= 0; st = back_[static_cast<std::size_t>(st)]) {
    const auto k = static_cast<std::size_t>(
                       std::upper_bound(slot_start.begin(), slot_start.end(), static_cast<std::size_t>(st)) - slot_start.begin()) - 1;
    best_.pairs.emplace_back(cause_[k], effect_[k]);
    best_.probability.push_back(posterior(cause_[k], effect_[k]));
  }
  std::reverse(best_.pairs.begin(), best_.pairs.end());
  std::reverse(best_.probability.begin(), best_.probability.end());
}

void AlignmentLattice::backward() {
  const std::size_t n = lo_.size(), m = effect_s_.size(), candidates = latency_.size();
  beta_.assign(candidates + pred_.size(), -INFINITY);
  // Per effect column: the later pairs drawn afresh there (their pair's factor and what follows),
  // brought back to the stamp by cause_loss per cause between.
  Columns columns(m, static_cast<std::int64_t>(n) - 1, log_loss_);
  Acc ahead;  // the columns from `unfolded` on, at stamp ahead_stamp
  std::int64_t ahead_stamp = static_cast<std::int64_t>(n) - 1;
  std::size_t unfolded = m;
  for (std::size_t i = n; i-- > 0;) {
    const auto now = static_cast<std::int64_t>(i);
    ahead = columns.moved(ahead, ahead_stamp, now);
    ahead_stamp = now;
    for (; unfolded > hi_[i]; --unfolded) {
      Acc shifted = ahead;
      shifted.v += log_unmatched_;
      ahead = combine(shifted, columns.at(unfolded - 1, now), false);
    }
    Acc later = ahead;  // every pair after cause i and after effect j drawn afresh, brought to (i, j)
    for (std::size_t j = hi_[i]; j-- > lo_[i];) {
      if (j + 1 < hi_[i]) {
        later.v += log_unmatched_;
        later = combine(later, columns.at(j + 1, now), false);
      }
      const auto k = index(i, j);
      const Acc base = combine({end(k)}, {fresh_ + later.v}, false);
      for (std::size_t s = 0; s < slots(k); ++s) {
        Acc sum = base;
        const auto carried = stretch(k, s);
        for (std::size_t e = succ_begin_[k]; e < succ_begin_[k + 1]; ++e) {
          const auto q = succ_[e];
          const auto k2 = pred_owner_[q];
          const double level = link_level_[q];
          const double link = carried ? log_keep_ + mix(sweep_part(q, *carried), level) : log_keep_ + level;
          sum = combine(sum, {log_kept_ + pred_skip_[q] + link + beta_[slot(k2, 1 + q - pred_begin_[k2])]}, false);
        }
        beta_[slot(k, s)] = sum.v;
      }
    }
    for (std::size_t j = lo_[i]; j < hi_[i]; ++j) columns.add(j, now - 1, {log_kept_ + beta_[slot(index(i, j), 0)]}, false);
  }
}

}  // namespace m2mlat::pairing
