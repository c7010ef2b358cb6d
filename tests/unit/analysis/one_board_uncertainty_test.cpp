// The uncertainty of a latency whose cause and effect one board stamped (two channels of one node:
// single-board glass-to-glass, the LED and the phototransistor on one board): the board's offset
// cancels, synchronised or not, and only its drift over the latency is left.
#include <gtest/gtest.h>

#include <cmath>

#include "m2mlat/analysis/uncertainty.hpp"

namespace m2mlat::analysis::one_board_uncertainty_test {
namespace {

constexpr std::int64_t kT0 = 1'780'304'400'000'000'000;
constexpr std::int64_t kMs = 1'000'000;

store::ClockSample sample(std::int64_t t_ns, bool synced, std::string source = "adjtimex") {
  store::ClockSample s;
  s.time = core::TimePoint::from_ns(core::Clock::realtime, t_ns);
  s.source = std::move(source);
  s.max_error_ns = synced ? 2 * kMs : kUnbounded;
  s.est_error_ns = synced ? 500'000 : kUnbounded;
  s.synchronised = synced;
  return s;
}

TEST(OneBoard, TheOffsetCancelsAndOnlyTheDriftOverTheLatencyIsLeft) {
  auto board = make_clock_track({sample(kT0, true)});
  board.node = "vehicle";
  UncertaintyOptions o;  // growth 15 ppm, kernel u 5 us
  o.calibration_max = core::Duration{50'000};
  o.calibration_u = core::Duration{20'000};
  const auto u = pair_uncertainty(board, board, kT0 + 10 * kMs, kT0 + 110 * kMs, o);
  EXPECT_EQ(u.flags, 0u);
  // 100 ms at 15 ppm: 1.5 us of drift at most; not the board's 2 ms bound twice.
  EXPECT_EQ(u.sync_max_ns, 1'500);
  EXPECT_EQ(u.max_error_ns, 1'500 + 50'000);
  const double drift = 1'500 / std::sqrt(3.0);
  EXPECT_EQ(u.u_ns, std::llround(std::sqrt(drift * drift + 2 * 5'000.0 * 5'000 + 20'000.0 * 20'000)));

  // The same tracks under two names are two boards: both offsets and both paths in full.
  auto other = board;
  other.node = "operator";
  const auto two = pair_uncertainty(board, other, kT0 + 10 * kMs, kT0 + 110 * kMs, o);
  EXPECT_GT(two.max_error_ns, 4 * kMs);
  EXPECT_GT(two.u_ns, 700'000);
}

TEST(OneBoard, NeedsNoSynchronisationButAStepStillFlags) {
  auto board = make_clock_track({sample(kT0, false)});
  board.node = "bench";
  const UncertaintyOptions o;
  const auto u = pair_uncertainty(board, board, kT0, kT0 + 30 * kMs, o);
  EXPECT_EQ(u.flags, 0u);
  EXPECT_TRUE(u.bounded());
  EXPECT_EQ(u.sync_max_ns, 450);  // 30 ms at 15 ppm

  auto stepped = make_clock_track({sample(kT0, false), sample(kT0 + 20 * kMs, false, "step")});
  stepped.node = "bench";
  EXPECT_EQ(pair_uncertainty(stepped, stepped, kT0, kT0 + 30 * kMs, o).flags, kUncertaintyClockStep);
  // Without any clock sample of the board the state stays unknown.
  ClockTrack empty;
  empty.node = "bench";
  EXPECT_EQ(pair_uncertainty(empty, empty, kT0, kT0 + 30 * kMs, o).flags, kUncertaintyNoClock);
}

}  // namespace
}  // namespace m2mlat::analysis::one_board_uncertainty_test
