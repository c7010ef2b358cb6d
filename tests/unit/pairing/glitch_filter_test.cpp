// The interference filter: which edges of a line recorded with both edges start a pulse.
#include "m2mlat/pairing/glitch_filter.hpp"

#include <gtest/gtest.h>

#include <cstdint>
#include <vector>

namespace m2mlat::pairing::glitch_filter_test {
namespace {

using Ns = std::vector<std::int64_t>;
constexpr std::int64_t kUs = 1'000, kMs = 1'000'000;
const core::Duration kWindow{1 * kMs};

TEST(GlitchFilter, KeepsPassesAndDropsShortPulses) {
  // A pass held 12 ms, a 5 us pulse, a pass held 2 ms, a 400 us pulse (shorter than the window).
  const Ns active{0, 100 * kMs, 200 * kMs, 300 * kMs};
  const Ns idle{12 * kMs, 100 * kMs + 5 * kUs, 202 * kMs, 300 * kMs + 400 * kUs};
  EXPECT_EQ(glitches(active, idle, kWindow), (Ns{1, 3}));
}

TEST(GlitchFilter, KeepsAPassWhoseStartChatters) {
  // Contact chatter in the pass's first 200 us, then held: every active edge of it starts a pulse
  // (the later ones are the refractory filter's bounces).
  const Ns active{50 * kMs, 50 * kMs + 100 * kUs, 50 * kMs + 200 * kUs};
  const Ns idle{50 * kMs + 50 * kUs, 50 * kMs + 150 * kUs, 65 * kMs};
  EXPECT_TRUE(glitches(active, idle, kWindow).empty());
}

TEST(GlitchFilter, KeepsAPassWhoseFirstBounceComesLate) {
  // The line up half-way to a bounce after the pass's edge, which is the pass's all the same:
  // 1.01 ms later, the edge active for 0.5 ms of the window after it (the simulator's seed 3), and
  // 2 ms later, 1 ms low and 1 ms high (seed 168).
  EXPECT_TRUE(glitches(Ns{0, 1'010 * kUs}, Ns{500 * kUs, 6 * kMs}, kWindow).empty());
  EXPECT_TRUE(glitches(Ns{0, 1'999 * kUs}, Ns{999 * kUs, 10 * kMs}, kWindow).empty());
}

TEST(GlitchFilter, DropsTheChatterOfARelease) {
  // The line released at 15 ms with chatter: its active edges start no pass (the first ends a short
  // dropout after a long pass, the last is a short pulse followed by rest).
  const Ns active{0, 15 * kMs + 100 * kUs, 15 * kMs + 300 * kUs};
  const Ns idle{15 * kMs, 15 * kMs + 200 * kUs, 15 * kMs + 400 * kUs};
  EXPECT_EQ(glitches(active, idle, kWindow), (Ns{1, 2}));
}

TEST(GlitchFilter, DropsAnEdgeInsideAPass) {
  // The line goes idle for 10 us inside a pass and back: that second active edge starts no pass.
  const Ns active{0, 5 * kMs + 10 * kUs};
  const Ns idle{5 * kMs, 20 * kMs};
  EXPECT_EQ(glitches(active, idle, kWindow), (Ns{1}));
}

TEST(GlitchFilter, APulseBeforeAPassIsDroppedAndThePassKept) {
  // Interference 3 ms before a true edge: the bounce rule alone would keep the interference's edge
  // and drop the pass's as a bounce, off by 3 ms. Within 2 w it would be the pass's chatter.
  const Ns active{97 * kMs, 100 * kMs};
  const Ns idle{97 * kMs + 3 * kUs, 110 * kMs};
  EXPECT_EQ(glitches(active, idle, kWindow), (Ns{0}));
  const Ns close_active{98 * kMs + 500 * kUs, 100 * kMs}, close_idle{98 * kMs + 503 * kUs, 110 * kMs};
  EXPECT_TRUE(glitches(close_active, close_idle, kWindow).empty());
}

TEST(GlitchFilter, OffOrNothingToFilter) {
  EXPECT_TRUE(glitches(Ns{0, kMs}, Ns{10, kMs + 10}, core::Duration{0}).empty());
  EXPECT_TRUE(glitches(Ns{}, Ns{5}, kWindow).empty());
  // Held to the end of the recording (no idle edge after it): a pass.
  EXPECT_TRUE(glitches(Ns{7 * kMs}, Ns{2 * kMs}, kWindow).empty());
}

TEST(GlitchFilter, EqualTimesEndIdle) {
  // A zero-width pulse (both edges stamped alike) is interference, not a pass held from then on.
  EXPECT_EQ(glitches(Ns{5 * kMs}, Ns{5 * kMs}, kWindow), (Ns{0}));
}

}  // namespace
}  // namespace m2mlat::pairing::glitch_filter_test
