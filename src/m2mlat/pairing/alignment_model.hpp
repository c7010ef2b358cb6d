// The model of how the two edge streams arise, from which the alignment of cause and effect edges
// and every pair's probability follow (docs/matcher.md, "Pairing as inference").
//
// Each cause edge has an effect edge (chance 1 - cause_loss) or none; effect edges without a cause
// (spurious, or their cause's edge lost) come at unmatched_per_s. The pairs keep the order of their
// causes. A pair's latency L depends on the previous pair's L' when no more than max_skip edges of
// either side lie unmatched between them: with the cause interval dc,
//   phi = exp(-dc / tau_s),
//   L ~ normal(mean_s + phi (L' - mean_s) + phi (stretch - 1) dc,
//              spread_s^2 (1 - phi^2) + (phi stretch_sd dc)^2 + 2 jitter_s^2)
// (within a sweep, dc << tau_s, the effect side replays the cause side's spacing times the stretch;
// over longer intervals the latency returns to its level, an Ornstein-Uhlenbeck process); with chance
// `reset`, and always after more unmatched edges than that, L is drawn afresh, uniform over the
// window (a stall, a handover: an excursion the link makes). A first pair's L is the level's:
// normal(mean_s, spread_s^2 + 2 jitter_s^2), or afresh with chance `reset`.
// The score of an alignment is the data's density under it: (1 - cause_loss) times the latency's
// density (1/s) per pair, cause_loss per cause left unmatched, unmatched_per_s (1/s) per effect left
// unmatched. Inside the model times are doubles in seconds; what comes in and goes out is int64 ns.
#pragma once

#include <cstddef>

namespace m2mlat::pairing {

struct AlignmentModel {
  double cause_loss = 0.02;       // chance that a cause edge has no effect edge
  double unmatched_per_s = 0.01;  // effect edges without a cause edge, per second
  double reset = 0.02;            // chance that a pair's latency is drawn afresh
  double mean_s = 0.8;            // the latency's level, s
  double spread_s = 0.1;          // its standard deviation about the level, s
  double tau_s = 30;              // its correlation time, s
  double stretch = 1;             // effect interval / cause interval within a sweep
  double stretch_sd = 0.2;        // the stretch's spread from sweep to sweep
  double jitter_s = 0.002;        // an edge's own timing noise, s
  std::size_t max_skip = 3;       // unmatched edges of a side between two pairs whose latencies are linked
  double min_latency_s = 0;       // the window a pair's latency lies in, s
  double max_latency_s = 10;
};

// Log densities of a pair's latency (1/s), each including the chance of a fresh draw.
double log_first_latency(const AlignmentModel& m, double latency_s);
// Linked to the previous pair's latency, the cause interval between them dc_s.
double log_linked_latency(const AlignmentModel& m, double latency_s, double previous_s, double dc_s);
// Not linked (more than max_skip unmatched edges between): the fresh draw only.
double log_fresh_latency(const AlignmentModel& m);
// The linked density without the fresh draw (its normal part, weighted by 1 - reset).
double log_link_only(const AlignmentModel& m, double latency_s, double previous_s, double dc_s);

}  // namespace m2mlat::pairing
