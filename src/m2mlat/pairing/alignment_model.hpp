// The model of how the two edge streams arise, from which the alignment of cause and effect edges
// and every pair's probability follow (docs/matcher.md, "Pairing as inference").
//
// Each cause edge has an effect edge (chance 1 - cause_loss) or none; effect edges without a cause
// (spurious, or their cause's edge lost) come at unmatched_per_s. The pairs keep the order of their
// causes. A pair's latency L is either drawn afresh (chance `reset`: uniform over the window, an
// excursion of the link such as a stall or a handover) or linked to the previous pair's L' (only when
// no more than max_skip edges of either side lie unmatched between them; else it is drawn afresh).
// A linked latency, over the cause interval dc, is
//   - with chance `sweep`, when the previous pair was linked too, the sweep going on: the effect side
//     replays the cause side's spacing at the stretch s1 of the previous link (its effect interval
//     over its cause interval): L ~ normal(L' + (s1 - 1) dc, (sweep_sd dc)^2 + 2 jitter_s^2);
//   - else the level's: with phi = exp(-dc / tau_s),
//     L ~ t4(mean_s + phi (L' - mean_s) + phi (stretch - 1) dc,
//            scale^2 = spread_s^2 (1 - phi^2) + (phi stretch_sd dc)^2 + 2 jitter_s^2)
//     (an Ornstein-Uhlenbeck process about the level, the log's usual stretch within a sweep; Student's
//     t with 4 degrees of freedom: an excursion of the link, a sweep a second late, is rare, not
//     impossible, so the true pairs of a late sweep are never traded for a shifted chain nearer the
//     level).
// A first pair's L is the level's, t4(mean_s, spread_s^2 + 2 jitter_s^2), or afresh (`reset`).
// The score of an alignment is the data's density under it, summed over which pairs were drawn
// afresh: (1 - cause_loss) times the latency's density (1/s) per pair, cause_loss per cause left
// unmatched, unmatched_per_s (1/s) per effect left unmatched. Inside the model times are doubles in
// seconds; what comes in and goes out is int64 ns.
#pragma once

#include <cstddef>
#include <optional>

namespace m2mlat::pairing {

struct AlignmentModel {
  double cause_loss = 0.02;       // chance that a cause edge has no effect edge
  double unmatched_per_s = 0.01;  // effect edges without a cause edge, per second
  double reset = 0.02;            // chance that a pair's latency is drawn afresh
  double mean_s = 0.8;            // the latency's level, s
  double spread_s = 0.1;          // its standard deviation about the level, s
  double tau_s = 30;              // its correlation time, s
  double stretch = 1;             // effect interval / cause interval within a sweep, the log's usual
  double stretch_sd = 0.2;        // its spread from sweep to sweep
  double sweep = 0.5;             // chance that a linked pair goes on with the previous link's stretch
  double sweep_sd = 0.05;         // how much the stretch changes from link to link within a sweep
  double jitter_s = 0.002;        // an edge's own timing noise, s
  std::size_t max_skip = 2;       // unmatched edges of a side between two pairs whose latencies are linked
  double min_latency_s = 0;       // the window a pair's latency lies in, s
  double max_latency_s = 10;
};

// log densities of a pair's latency (1/s).
// A first pair's (the level's or afresh).
double log_first_latency(const AlignmentModel& m, double latency_s);
// Drawn afresh, the chance `reset` included.
double log_fresh_latency(const AlignmentModel& m);
// Linked to the previous pair's latency, the chance 1 - reset included; previous_stretch: the
// previous link's (unset when the previous pair was not linked).
double log_linked_latency(const AlignmentModel& m, double latency_s, double previous_s, double dc_s,
                          std::optional<double> previous_stretch);
// Its two parts, for a caller that needs one latency with several previous stretches: the level's
// normal (no chance factors), and the sweep's; log_linked_latency = log(1 - reset) + (a stretch ?
// log(sweep e^sweep_part + (1 - sweep) e^level_part) : level_part).
double log_level_link(const AlignmentModel& m, double latency_s, double previous_s, double dc_s);
double log_sweep_link(const AlignmentModel& m, double latency_s, double previous_s, double dc_s, double previous_stretch);

}  // namespace m2mlat::pairing
