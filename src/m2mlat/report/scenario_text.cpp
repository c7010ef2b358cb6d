// Text tables of scenario results (the numbers are in ms with 1 decimal; CSV/JSON carry full precision).
#include "m2mlat/report/scenario_text.hpp"

#include <fmt/format.h>

#include "m2mlat/analysis/kernel_log_steps.hpp"
#include "m2mlat/analysis/pairing_counts.hpp"
#include "m2mlat/core/printable.hpp"
#include "m2mlat/core/time.hpp"
#include "m2mlat/report/resampling_text.hpp"
#include "m2mlat/report/table.hpp"

namespace m2mlat::report {

namespace {
// ">1s", ">170ms", ">2.5ms"
std::string threshold_name(core::Duration d) {
  if (d.count() % 1'000'000'000 == 0) return fmt::format(">{}s", d.count() / 1'000'000'000);
  std::string ms = core::format_ms(d);
  ms.erase(ms.find_last_not_of('0') + 1);
  if (ms.back() == '.') ms.pop_back();
  return ">" + ms + "ms";
}
}  // namespace

std::vector<std::string> summary_cells(const stats::Summary& s) {
  std::vector<std::string> cells{std::to_string(s.n),
                                 ms_text(s.median_ms),
                                 ms_text(s.iqr_ms),
                                 ms_text(s.mean_ms),
                                 ms_text(s.sd_ms),
                                 s.min ? ms_text(s.min->ms()) : "-",
                                 s.max ? ms_text(s.max->ms()) : "-",
                                 ms_text(s.p95_ms)};
  for (const auto& t : s.thresholds) cells.push_back(percent_text(t.fraction_above));
  return cells;
}

std::string scenario_table(std::span<const analysis::ScenarioResult> results) {
  std::vector<std::string> header{"scenario", "n", "median", "IQR", "mean", "sd", "min", "max", "P95"};
  if (!results.empty())
    for (const auto& t : results.front().summary.thresholds) header.push_back(threshold_name(t.threshold));
  Table table(header);
  for (const auto& r : results) {
    std::vector<std::string> row{r.input.scenario};
    for (auto& cell : summary_cells(r.summary)) row.push_back(std::move(cell));
    row.resize(header.size(), "-");
    table.add_row(std::move(row));
  }
  return "latency (ms) of the n pairs in the statistics\n" + table.render();
}

std::string pairing_table(std::span<const analysis::ScenarioResult> results) {
  Table table({"scenario", "cause (edges)", "effect (edges)", "pairs", "flagged", "in statistics",
               "cause unmatched", "effect unmatched", "bounces"});
  for (const auto& r : results) {
    const auto c = analysis::pairing_counts(r);
    table.add_row({r.input.scenario, fmt::format("{} ({})", core::to_string(r.input.cause_ref), c.cause.edges),
                   fmt::format("{} ({})", core::to_string(r.input.effect_ref), c.effect.edges),
                   std::to_string(c.pairs), std::to_string(c.flagged), std::to_string(c.in_statistics),
                   std::to_string(c.cause.unpaired()), std::to_string(c.effect.unpaired()),
                   std::to_string(c.bounces())});
  }
  std::string caption =
      "pairing (pairs: matched; flagged: with a pairing flag, left out unless --include-ambiguous; in "
      "statistics: the n of the latency table; unmatched: edges without partner, bounces apart; bounces: "
      "edges dropped within --refractory of a kept one, both sides)\n";
  std::string notes;  // what was left out before pairing: interference (--min-pulse), no known clock
  for (const auto& r : results)
    if (const auto& g = r.input.glitches)
      notes += fmt::format(
          "{}: {} cause and {} effect edges started no pulse of {} ms (dropped as interference, before pairing)\n",
          r.input.scenario, g->cause, g->effect, ms_text(static_cast<double>(g->min_pulse.count()) / 1e6, 3));
  for (const auto& r : results)
    for (const auto& w : r.warnings) notes += fmt::format("warning: {}: {}\n", r.input.scenario, w.text);
  for (const auto& r : results)  // the alignment model's fit and expectation (--matcher model)
    if (const auto& m = r.match.model) {
      const auto& p = m->parameters;
      notes += fmt::format(
          "{}: model: latency {} ms (spread {} ms, correlation time {:.3g} s), sweep stretch {:.3g} (sd {:.3g}), "
          "jitter {} ms, cause edges without effect {:.3g} %, effect edges without cause {:.3g} /min, fresh "
          "latencies {:.3g} %; {} pairs at p >= {:g}, {:.2f} of them expected wrong\n",
          r.input.scenario, ms_text(p.mean_s * 1e3, 1), ms_text(p.spread_s * 1e3, 1), p.tau_s, p.stretch,
          p.stretch_sd, ms_text(p.jitter_s * 1e3, 2), 100 * p.cause_loss, 60 * p.unmatched_per_s, 100 * p.reset,
          m->kept, m->min_probability, m->expected_wrong);
    }
  for (const auto& r : results) {  // the events on no known clock, before pairing (docs/sync.md)
    const auto& c = r.input.cause_unknown_clock;
    const auto& e = r.input.effect_unknown_clock;
    if (c.total() + e.total() != 0)
      notes += fmt::format(
          "{}: {} cause and {} effect events left out, their stamps on no known clock ({} outliers that disagree "
          "with the lines on both sides, {} before the board's first synchronisation)\n",
          r.input.scenario, c.total(), e.total(), c.outlier + e.outlier, c.before_sync + e.before_sync);
  }
  return caption + table.render() + notes;
}

std::string uncertainty_table(std::span<const analysis::ScenarioResult> results) {
  Table table({"scenario", "with clock", "median u", "median U95", "median max_err", "P95 max_err",
               "worst max_err", "flagged", "step", "unsync", "gated", "refused"});
  bool any = false;
  for (const auto& r : results) {
    if (r.uncertainty.empty()) continue;
    any = true;
    const auto u = analysis::summarize_uncertainty(r.uncertainty, r.refuse_gated);
    table.add_row({r.input.scenario, fmt::format("{}/{}", u.known, u.samples), ms_text(u.median_u_ms, 3),
                   ms_text(u.median_U95_ms, 3), ms_text(u.median_max_ms, 3), ms_text(u.p95_max_ms, 3),
                   ms_text(u.worst_max_ms, 3), percent_text(u.share_flagged()), std::to_string(u.clock_step),
                   std::to_string(u.unsynchronised), std::to_string(u.gated), std::to_string(u.refused)});
  }
  if (!any) return {};
  return "per-sample uncertainty (ms; u = standard uncertainty, k = 1, of the clocks, the kernel and the "
         "calibration (--misalignment/--rate or --calibration-u); U95 = 2 u, about 95 %; max_err = worst case: "
         "both clocks' bounds + kernel + calibration bounds + bounces; docs/precision.md)\n" +
         table.render();
}

std::vector<std::string> flagged_effect_header() {
  return {"scenario", "flagged", "in statistics", "median without", "median with", "IQR without", "IQR with",
          "moves by more than half the CI"};
}

std::vector<std::string> flagged_effect_row(const analysis::ScenarioResult& r) {
  if (!r.flagged_effect) return {};
  const auto& e = *r.flagged_effect;
  std::string moves;
  if (e.median_moves())
    moves = fmt::format("median {:+.1f} (half CI {:.1f})", e.median_shift_ms(), *e.half_median_ci_ms);
  if (e.iqr_moves())
    moves += fmt::format("{}IQR {:+.1f} (half CI {:.1f})", moves.empty() ? "" : "; ", e.iqr_shift_ms(),
                         *e.half_iqr_ci_ms);
  if (moves.empty()) moves = e.half_median_ci_ms ? "no" : "- (no CI)";
  return {r.input.scenario, std::to_string(e.flagged), e.included ? "yes" : "no", ms_text(e.median_without_ms),
          ms_text(e.median_with_ms), ms_text(e.iqr_without_ms), ms_text(e.iqr_with_ms), moves};
}

std::string flagged_effect_table(std::span<const analysis::ScenarioResult> results) {
  Table table(flagged_effect_header());
  bool any = false;
  for (const auto& r : results)
    if (auto row = flagged_effect_row(r); !row.empty()) {
      table.add_row(std::move(row));
      any = true;
    }
  if (!any) return {};
  return "what the flagged pairs do (ms; \"in statistics\": the statistics above hold them, "
         "--include-ambiguous)\n" +
         table.render();
}

std::vector<std::string> clock_limit_notes(const analysis::ScenarioResult& r) {
  std::vector<std::string> out;
  for (const auto& [side, ref] : {std::pair{&r.steps.cause, &r.input.cause_ref}, std::pair{&r.steps.effect, &r.input.effect_ref}})
    for (const auto& note : analysis::log_clock_notes(side->limits))
      out.push_back(fmt::format("{}: {}", core::printable(ref->node), note));
  return out;
}

std::string clock_step_table(std::span<const analysis::ScenarioResult> results) {
  Table table({"scenario", "cause steps", "effect steps", "pairs corrected", "after step (left out)"});
  bool any = false;
  std::string notes;
  for (const auto& r : results) {
    if (r.steps.steps() == 0 && !r.steps.limited()) continue;
    any = true;
    table.add_row({r.input.scenario, std::to_string(r.steps.cause.steps), std::to_string(r.steps.effect.steps),
                   std::to_string(r.pairs_marked(analysis::StepMark::corrected)),
                   std::to_string(r.pairs_marked(analysis::StepMark::unknown))});
    for (const auto& side : clock_limit_notes(r)) notes += fmt::format("note: {}: {}\n", r.input.scenario, side);
  }
  if (!any) return {};
  return "clock steps (later events brought back by a step's known size; of unknown size: flagged, left out)\n" +
         table.render() + notes;
}

std::string scenario_detail(const analysis::ScenarioResult& r) {
  const auto& s = r.summary;
  std::string out =
      fmt::format("scenario {}: {} -> {}, {} pairs{}\n", core::printable(r.input.scenario),
                  core::printable(core::to_string(r.input.cause_ref)),
                  core::printable(core::to_string(r.input.effect_ref)), s.n,
                  (r.include_ambiguous ? std::string(" (ambiguous included)")
                                       : fmt::format(" ({} ambiguous left out)", r.ambiguous_pairs())) +
                      (r.pairs_marked(analysis::StepMark::unknown) == 0
                           ? std::string()
                           : fmt::format(" ({} after a clock step left out)",
                                         r.pairs_marked(analysis::StepMark::unknown))));
  Table table({"statistic", "value (ms)", "note"});
  auto extreme = [&](const char* name, const std::optional<stats::Extreme>& e) {
    if (e)
      table.add_row({name, ms_text(e->ms(), 3), fmt::format("cause event {} {}", r.input.id_kind, e->id)});
  };
  extreme("min", s.min);
  table.add_row({"P5", ms_text(s.p5_ms, 3), ""});
  table.add_row({"Q1", ms_text(s.q1_ms, 3), ""});
  auto ci = [&](stats::Interval stats::MedianIqrCi::*which) {
    if (!s.bootstrap) return std::string();
    const auto& i = (*s.bootstrap).*which;
    return fmt::format("{:.0f}% CI {:.3f} .. {:.3f}", 100 * s.bootstrap->level, i.lower, i.upper);
  };
  table.add_row({"median", ms_text(s.median_ms, 3), ci(&stats::MedianIqrCi::median_ms)});
  table.add_row({"Q3", ms_text(s.q3_ms, 3), ""});
  table.add_row({"P90", ms_text(s.p90_ms, 3), ""});
  table.add_row({"P95", ms_text(s.p95_ms, 3), ""});
  table.add_row({"P99", ms_text(s.p99_ms, 3), ""});
  extreme("max", s.max);
  table.add_row({"IQR", ms_text(s.iqr_ms, 3), ci(&stats::MedianIqrCi::iqr_ms)});
  table.add_row({"mean", ms_text(s.mean_ms, 3), ""});
  table.add_row({"sd", ms_text(s.sd_ms, 3), "n - 1"});
  for (const auto& p : s.extra_percentiles)
    table.add_row({fmt::format("P{}", p.percent), ms_text(p.value_ms, 3), ""});
  for (const auto& t : s.thresholds)
    table.add_row({threshold_name(t.threshold), percent_text(t.fraction_above, 2),
                   fmt::format("{} samples", t.count_above)});
  out += table.render();
  if (s.bootstrap)
    out += fmt::format("CIs: {} resamples; {}\n", s.bootstrap->resamples, resampling_text(s.bootstrap->resampling));
  return out;
}

}  // namespace m2mlat::report
