// Wording of comparisons. Ratios below 1 are said as "narrower"/"smaller", above as "wider"/"larger",
// with the CI turned the same way, so the sentence reads as the reference study's did.
#include "m2mlat/report/comparison_text.hpp"

#include <fmt/format.h>

#include <cmath>

#include "m2mlat/core/printable.hpp"
#include "m2mlat/report/resampling_text.hpp"
#include "m2mlat/report/table.hpp"

namespace m2mlat::report {

namespace {
std::string level_text(double level) { return fmt::format("{:g} %", level * 100); }

// "47 % narrower (95 % CI 21 to 62 %)" for a ratio and its CI.
std::string ratio_words(const char* what, double ratio, const stats::Interval& ci, double level,
                        const char* less, const char* more) {
  if (std::isnan(ratio)) return fmt::format("{} ratio undefined", what);
  const bool smaller = ratio < 1.0;
  const double change = smaller ? (1.0 - ratio) * 100 : (ratio - 1.0) * 100;
  std::string out = fmt::format("{} {:.0f} % {}", what, change, smaller ? less : more);
  if (!std::isnan(ci.lower)) {
    const double lo = smaller ? (1.0 - ci.upper) * 100 : (ci.lower - 1.0) * 100;
    const double hi = smaller ? (1.0 - ci.lower) * 100 : (ci.upper - 1.0) * 100;
    out += fmt::format(" ({} CI {:.0f} to {:.0f} %)", level_text(level), lo, hi);
  }
  return out;
}

std::string verdict(double p, double alpha) {
  return p < alpha ? "significant" : fmt::format("not significant at {:g}", alpha);
}

std::string threshold_text(core::Duration t) {
  const auto ns = t.count();
  if (ns % 1'000'000'000 == 0) return fmt::format("{} s", ns / 1'000'000'000);
  if (ns % 1'000'000 == 0) return fmt::format("{} ms", ns / 1'000'000);
  return fmt::format("{:g} ms", static_cast<double>(ns) / 1e6);
}
}  // namespace

std::string p_text(double p) {
  if (std::isnan(p)) return "p = -";
  if (p < 0.0001) return "p < 0.0001";
  return fmt::format("p = {:.2g}", p);
}

std::string comparison_sentence(const ComparisonReport& r) {
  const auto& c = r.comparison;
  std::string s = fmt::format("{} vs {}: ", core::printable(r.subject), core::printable(r.baseline));
  s += ratio_words("IQR", c.iqr_ratio, c.iqr_ratio_ci, c.level, "narrower", "wider");
  s += fmt::format(", {} (Brown-Forsythe, {})", p_text(c.brown_forsythe.p),
                   verdict(c.brown_forsythe.p, c.alpha));
  s += fmt::format("; median {:+.1f} ms", c.median_difference_ms);
  if (!std::isnan(c.median_difference_ci_ms.lower))
    s += fmt::format(" ({} CI {:+.1f} to {:+.1f} ms)", level_text(c.level), c.median_difference_ci_ms.lower,
                     c.median_difference_ci_ms.upper);
  s += fmt::format(", {} (Mann-Whitney, {})", p_text(c.mann_whitney.p), verdict(c.mann_whitney.p, c.alpha));
  s += "; " + ratio_words("SD", c.sd_ratio, c.sd_ratio_ci, c.level, "smaller", "larger");
  for (const auto& d : c.shares)
    // A limit that every sample (or none) of both exceeds says nothing about the difference.
    if (d.count_subject + d.count_baseline > 0 &&
        (d.count_subject < c.n_subject || d.count_baseline < c.n_baseline))
      s += fmt::format("; above {}: {:.1f} % vs {:.1f} % ({:+.1f} points, CI {:+.1f} to {:+.1f})",
                       threshold_text(d.threshold), d.share_subject * 100, d.share_baseline * 100,
                       d.difference * 100, d.ci.lower * 100, d.ci.upper * 100);
  if (c.resamples > 0)
    s += fmt::format("; the CIs resampled {} of {} and {} of {}", resampling_name(c.subject_resampling),
                     core::printable(r.subject), resampling_name(c.baseline_resampling), core::printable(r.baseline));
  s += ".";
  const auto note = uncertainty_note(r);
  if (!note.empty()) s += " " + note;
  return s;
}

std::string uncertainty_note(const ComparisonReport& r) {
  const auto& c = r.comparison;
  if (!c.uncertainty_ms) return {};
  std::string s;
  if (c.median_difference_below_uncertainty)
    s += fmt::format(
        "Note: the median difference ({:.3f} ms) is smaller than the measurement uncertainty "
        "({:.3f} ms).",
        std::fabs(c.median_difference_ms), *c.uncertainty_ms);
  if (c.iqr_difference_below_uncertainty)
    s += fmt::format(
        "{}Note: the IQR difference ({:.3f} ms) is smaller than the measurement uncertainty "
        "({:.3f} ms).",
        s.empty() ? "" : " ", std::fabs(c.iqr_subject_ms - c.iqr_baseline_ms), *c.uncertainty_ms);
  return s;
}

std::string comparison_table(std::span<const ComparisonReport> comparisons) {
  Table t({"subject vs baseline", "median diff (ms)", "CI", "Mann-Whitney", "IQR ratio", "CI", "SD ratio",
           "CI", "Brown-Forsythe"});
  for (const auto& r : comparisons) {
    const auto& c = r.comparison;
    const auto ci = [](const stats::Interval& i, int decimals) {
      return std::isnan(i.lower) ? std::string("-")
                                 : fmt::format("{:.{}f} .. {:.{}f}", i.lower, decimals, i.upper, decimals);
    };
    t.add_row({r.subject + " vs " + r.baseline, fmt::format("{:+.1f}", c.median_difference_ms),
               ci(c.median_difference_ci_ms, 1), p_text(c.mann_whitney.p), fmt::format("{:.3f}", c.iqr_ratio),
               ci(c.iqr_ratio_ci, 3), fmt::format("{:.3f}", c.sd_ratio), ci(c.sd_ratio_ci, 3),
               p_text(c.brown_forsythe.p)});
  }
  return t.render();
}

}  // namespace m2mlat::report
