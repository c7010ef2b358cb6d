#include "m2mlat/onset/flank.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

#include "m2mlat/core/error.hpp"
#include "m2mlat/onset/hinge_fit.hpp"
#include "m2mlat/onset/option_check.hpp"
#include "m2mlat/onset/uncertainty.hpp"

namespace m2mlat::onset {

namespace {

using Vec3 = std::array<double, 3>;

void check_options(const FlankOptions& o) {
  constexpr std::string_view kWho = "flank detector";
  check_rest_options(kWho, o);
  if (!(o.min_peak_deg_s >= 0)) option_out_of_range(kWho, "min_peak_deg_s", o.min_peak_deg_s);
  if (!(o.fit_fraction > 0 && o.fit_fraction < 1)) option_out_of_range(kWho, "fit_fraction", o.fit_fraction);
  if (o.lookback_ns < 0) option_out_of_range(kWho, "lookback_ns", static_cast<double>(o.lookback_ns));
}

class FlankPass {
 public:
  FlankPass(const core::RateTrace& trace, const FlankOptions& o)
      : s_(trace.samples),
        o_(o),
        scale_(1.0 / trace.counts_per_deg_s),
        // A rate is known to a count at best: the noise floor of a still chip (rounding and drift).
        min_var_(scale_ * scale_) {}

  Detection run() {
    for (std::size_t i = 0; i < s_.size(); ++i) step(i);
    if (state_ == State::moving) finish(s_.size() - 1, s_.size() - 1, false);
    return std::move(out_);
  }

 private:
  enum class State { learning, armed, moving };

  Vec3 rates(std::size_t i) const {
    return {s_[i].raw[0] * scale_, s_[i].raw[1] * scale_, s_[i].raw[2] * scale_};
  }

  void start_learning(std::size_t i) {
    state_ = State::learning;
    learn_from_ = i;
    n_ = 0;
    mean_ = {};
    m2_ = {};
  }

  void step(std::size_t i) {
    const Vec3 x = rates(i);
    if (state_ == State::learning) {
      learn(i, x);
      return;
    }
    double mag2 = 0;
    Vec3 d;
    for (std::size_t a = 0; a < 3; ++a) {
      d[a] = x[a] - bias_[a];
      smooth_[a] += o_.smooth_alpha * (d[a] - smooth_[a]);
      mag2 += smooth_[a] * smooth_[a];
    }
    const bool above = mag2 > threshold2_;
    if (state_ == State::armed) {
      if (above) {
        state_ = State::moving;
        detect_ = last_above_ = peak_index_ = i;
        peak2_ = mag2;
        peak_dir_ = smooth_;
        return;
      }
      // Still: follow the rest level and the noise slowly (a drifting bias).
      for (std::size_t a = 0; a < 3; ++a) {
        bias_[a] += o_.rest_alpha * d[a];
        var_[a] = std::max(min_var_, var_[a] + o_.rest_alpha * (d[a] * d[a] - var_[a]));
      }
      update_threshold();
      return;
    }
    // Moving.
    if (above) {
      last_above_ = i;
      if (mag2 > peak2_) peak2_ = mag2, peak_index_ = i, peak_dir_ = smooth_;
    } else if (s_[i].time_ns - s_[last_above_].time_ns >= o_.quiet_ns) {
      finish(last_above_, i, true);
      state_ = State::armed;
    }
  }

  void learn(std::size_t i, const Vec3& x) {
    ++n_;
    for (std::size_t a = 0; a < 3; ++a) {  // Welford's running mean and sum of squared deviations
      const double delta = x[a] - mean_[a];
      mean_[a] += delta / static_cast<double>(n_);
      m2_[a] += delta * (x[a] - mean_[a]);
    }
    if (s_[i].time_ns - s_[learn_from_].time_ns < o_.learn_ns || n_ < 16) return;
    for (std::size_t a = 0; a < 3; ++a) {
      const double sd = std::sqrt(m2_[a] / static_cast<double>(n_ - 1));
      if (sd > o_.max_rest_sd_deg_s || std::abs(mean_[a]) > o_.max_bias_deg_s) {
        // Not rest: a motion under way. Before any motion was found, the trace began in one.
        if (out_.motions.empty()) out_.began_in_motion = true;
        start_learning(i + 1);
        return;
      }
    }
    for (std::size_t a = 0; a < 3; ++a) {
      bias_[a] = mean_[a];
      var_[a] = std::max(min_var_, m2_[a] / static_cast<double>(n_ - 1));
    }
    smooth_ = {};
    update_threshold();
    state_ = State::armed;
  }

  void update_threshold() {
    // Each smoothed axis has variance var * alpha / (2 - alpha) at rest; the magnitude squared sums
    // the three.
    const double f = o_.smooth_alpha / (2 - o_.smooth_alpha);
    threshold2_ = o_.k * o_.k * (var_[0] + var_[1] + var_[2]) * f;
  }

  // The rate along the motion's direction, minus the rest level, over [from, to] into p_, t_.
  void project(std::size_t from, std::size_t to, const Vec3& u) {
    t_.clear();
    p_.clear();
    for (std::size_t j = from; j <= to; ++j) {
      const Vec3 x = rates(j);
      t_.push_back(s_[j].time_ns);
      p_.push_back(u[0] * (x[0] - bias_[0]) + u[1] * (x[1] - bias_[1]) + u[2] * (x[2] - bias_[2]));
    }
  }

  std::size_t index_at(std::int64_t t) const {  // the first sample at or after t
    return static_cast<std::size_t>(
        std::lower_bound(s_.begin(), s_.end(), t,
                         [](const core::RateSample& a, std::int64_t v) { return a.time_ns < v; }) -
        s_.begin());
  }

  std::int64_t combined_sd(const HingeFit& fit) const {
    const double stamp = stamp_sd_ns(s_[std::min(index_at(fit.t0_ns), s_.size() - 1)]);
    return std::llround(std::sqrt(fit.sd_ns * fit.sd_ns + stamp * stamp));
  }

  // The motion detected at detect_, last above the threshold at `last`, declared over at `now`.
  void finish(std::size_t last, std::size_t now, bool ended) {
    const double peak = std::sqrt(peak2_);
    if (peak < o_.min_peak_deg_s) return;  // a bump
    Vec3 u = peak_dir_;
    for (auto& v : u) v /= peak;
    const double level = o_.fit_fraction * peak;

    Motion m;
    m.peak_deg_s = peak;
    m.ended = ended;
    // Onset: from well before the detection up to the first sample at the fit level.
    std::size_t reach = detect_;
    while (reach < peak_index_ && along(reach, u) < level) ++reach;
    const std::int64_t span = s_[reach].time_ns - s_[detect_].time_ns;
    std::size_t from = index_at(s_[detect_].time_ns - std::max(o_.lookback_ns, 3 * span));
    from = std::max(from, floor_);
    project(from, reach, u);
    const auto onset = fit_hinge(t_, p_, true);
    m.onset_ns = onset.valid ? onset.t0_ns : s_[detect_].time_ns;
    m.onset_sd_ns = onset.valid ? combined_sd(onset) : crossing_sd_ns(s_, detect_);

    if (ended) {
      std::size_t back = last;
      while (back > peak_index_ && along(back, u) < level) --back;
      const std::int64_t tail = s_[last].time_ns - s_[back].time_ns;
      const std::size_t to = std::min(
          s_.size() - 1, std::max(now, index_at(s_[last].time_ns + std::max(o_.lookback_ns, 3 * tail))));
      project(back, to, u);
      const auto end = fit_hinge(t_, p_, false);
      m.end_ns = end.valid ? end.t0_ns : s_[last].time_ns;
      m.end_sd_ns = end.valid ? combined_sd(end) : crossing_sd_ns(s_, last);
      floor_ = to;
    } else {
      m.end_ns = s_.back().time_ns;
      floor_ = s_.size() - 1;
    }
    out_.motions.push_back(m);
  }

  double along(std::size_t j, const Vec3& u) const {
    const Vec3 x = rates(j);
    return u[0] * (x[0] - bias_[0]) + u[1] * (x[1] - bias_[1]) + u[2] * (x[2] - bias_[2]);
  }

  const std::vector<core::RateSample>& s_;
  const FlankOptions& o_;
  const double scale_;
  const double min_var_;
  Detection out_;
  State state_ = State::learning;
  // Learning (Welford).
  std::size_t learn_from_ = 0;
  std::int64_t n_ = 0;
  Vec3 mean_{}, m2_{};
  // The rest level and noise variance per axis (deg/s, (deg/s)^2), the detection average.
  Vec3 bias_{}, var_{}, smooth_{};
  double threshold2_ = 0;
  // The motion under way.
  std::size_t detect_ = 0, last_above_ = 0, peak_index_ = 0;
  double peak2_ = 0;
  Vec3 peak_dir_{};
  std::size_t floor_ = 0;        // no fit window reaches before this sample (the last motion's window)
  std::vector<std::int64_t> t_;  // the fit window, reused from motion to motion
  std::vector<double> p_;
};

}  // namespace

Detection detect_flank(const core::RateTrace& trace, const FlankOptions& options) {
  check_trace(trace);
  check_options(options);
  return FlankPass(trace, options).run();
}

}  // namespace m2mlat::onset
