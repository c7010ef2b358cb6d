// The gyroscope as a recorder channel: samples numbered in read order and cut into blocks, the
// sampler's missed periods and I2C errors as losses, and the keep window: on the gyroscope twin's
// motions, every sample within the window of a true motion is stored and the still samples more than
// 0.2 s beyond it are left out, with the jump visible in the blocks' numbers.
#include "m2mlat/capture/gyro_channel.hpp"

#include <gtest/gtest.h>

#include <map>
#include <vector>

#include "m2mlat/core/error.hpp"
#include "m2mlat/sim/gyro.hpp"
#include "m2mlat/sim/gyro_motion.hpp"
#include "m2mlat/store/rate_block.hpp"

namespace m2mlat::capture::gyro_channel_test {
namespace {

core::TimePoint rt(std::int64_t ns) { return core::TimePoint::from_ns(core::Clock::realtime, ns); }

std::vector<core::RateSample> still(std::size_t n, std::int64_t t0) {
  std::vector<core::RateSample> out(n);
  for (std::size_t i = 0; i < n; ++i) out[i].time_ns = t0 + static_cast<std::int64_t>(i) * 125'000;
  return out;
}

TEST(GyroChannel, KeepsEverySampleNumberedAndRecordsTheSamplersLosses) {
  GyroChannel channel("gyro", core::Clock::realtime, 131.0, {});
  GyroSummary summary;
  channel.add(still(5000, 0), summary);
  std::vector<store::RateBlock> blocks;
  std::vector<store::Loss> losses;
  channel.collect({7, rt(0), {}, false}, rt(1), blocks, losses);
  ASSERT_EQ(blocks.size(), 2u);  // 4096 + 904
  EXPECT_EQ(blocks[0].samples.size(), store::rate_block::kMaxSamples);
  EXPECT_EQ(blocks[1].first_index, store::rate_block::kMaxSamples);
  EXPECT_EQ(blocks[1].session_id, 7);
  EXPECT_TRUE(losses.empty());

  summary.missed_periods = 3;
  summary.i2c_errors = 1;
  channel.add(still(10, 5000 * 125'000), summary);
  blocks.clear();
  channel.collect({7, rt(0), {}, true}, rt(2), blocks, losses);
  ASSERT_EQ(blocks.size(), 1u);
  EXPECT_EQ(blocks[0].first_index, 5000u);
  ASSERT_EQ(losses.size(), 2u);
  EXPECT_EQ(losses[0].kind, "missed_period");
  EXPECT_EQ(losses[0].count, 3u);
  EXPECT_EQ(losses[0].first_missing, 5010u);
  EXPECT_EQ(losses[0].channel, "gyro");
  EXPECT_EQ(losses[0].detected_at, rt(2));
  EXPECT_EQ(losses[1].kind, "i2c_error");
  EXPECT_EQ(channel.counters().stored, 5010u);
  EXPECT_EQ(channel.counters().left_out, 0u);
}

// The agent's sessions: a sample goes to the session it was sampled in. Session 3 runs from 0 to
// 1 s; nothing is open from 1 s to 1.5 s; session 4 begins at 1.5 s. The samples come in rounds that
// straddle the boundaries, as the sampler hands them over.
TEST(GyroChannel, EachSampleGoesToTheSessionItWasSampledInAndNoneBetweenSessions) {
  const std::int64_t ms = 1'000'000;
  for (const std::int64_t window : {std::int64_t{0}, 200 * ms}) {
    GyroChannel channel("gyro", core::Clock::realtime, 131.0, {core::Duration{window}});
    std::vector<store::RateBlock> blocks;
    std::vector<store::Loss> losses;
    const auto samples = still(24'000, 0);  // 3 s at 8 kHz
    const auto feed = [&](std::int64_t to_ns) {
      std::vector<core::RateSample> part;
      for (const auto& x : samples)
        if (x.time_ns >= to_ns - 100 * ms && x.time_ns < to_ns) part.push_back(x);
      channel.add(std::move(part), {});
    };
    for (std::int64_t t = 100 * ms; t <= 1000 * ms; t += 100 * ms) {
      feed(t);
      channel.collect({3, rt(0), {}, false}, rt(t), blocks, losses);
    }
    feed(1100 * ms);  // the end's round: samples after the end wait
    channel.collect({3, rt(0), rt(1000 * ms - 1), false}, rt(1100 * ms), blocks, losses);
    for (std::int64_t t = 1200 * ms; t <= 1500 * ms; t += 100 * ms) {
      feed(t);
      channel.collect({0, {}, {}, false}, rt(t), blocks, losses);  // no session open
    }
    for (std::int64_t t = 1600 * ms; t <= 3000 * ms; t += 100 * ms) {
      feed(t);
      channel.collect({4, rt(1500 * ms), {}, t == 3000 * ms}, rt(t), blocks, losses);
    }
    std::map<std::int64_t, std::pair<std::int64_t, std::int64_t>> span;  // session -> first, last ns
    std::map<std::int64_t, std::uint64_t> count;
    for (const auto& b : blocks) {
      auto& [first, last] = span.try_emplace(b.session_id, b.samples.front().time_ns, 0).first->second;
      first = std::min(first, b.samples.front().time_ns);
      last = std::max(last, b.samples.back().time_ns);
      count[b.session_id] += b.samples.size();
      EXPECT_EQ(b.samples.front().time_ns, static_cast<std::int64_t>(b.first_index) * 125'000);
    }
    EXPECT_EQ(channel.counters().stored + channel.counters().left_out + channel.counters().outside_session,
              24'000u);
    for (const auto& [session, first_last] : span) {
      EXPECT_TRUE(session == 3 ? first_last.second < 1000 * ms : first_last.first >= 1500 * ms)
          << "window " << window << ": a block of session " << session << " crosses a boundary";
    }
    if (window > 0) {  // the rest is all still: the window keeps nothing
      EXPECT_TRUE(blocks.empty());
      continue;
    }
    ASSERT_EQ(span.size(), 2u);
    EXPECT_EQ(span[3].first, 0);
    EXPECT_EQ(span[3].second, 1000 * ms - 125'000);
    EXPECT_EQ(span[4].first, 1500 * ms);
    EXPECT_EQ(span[4].second, 3000 * ms - 125'000);
    EXPECT_EQ(count[3], 8000u);
    EXPECT_EQ(count[4], 12'000u);
    EXPECT_EQ(channel.counters().outside_session, 4000u);  // 1 s .. 1.5 s
  }
}

TEST(GyroChannel, TheKeepFlagIsAllOrAWindowInMilliseconds) {
  EXPECT_EQ(parse_gyro_keep("--gyro-keep", "all").window.count(), 0);
  EXPECT_EQ(parse_gyro_keep("--gyro-keep", "window:250").window.count(), 250'000'000);
  for (const char* bad : {"window:", "window:0", "window:-5", "window:2s", "some", ""})
    EXPECT_THROW(parse_gyro_keep("--gyro-keep", bad), core::Error) << bad;
}

// 24 s of the twin at 8 kHz with two hand motions; the channel is fed in 100 ms rounds, as the
// recorder's commit interval gives them.
TEST(GyroChannel, TheKeepWindowStoresEverythingAroundEachMotionAndLeavesOutTheStillRest) {
  const std::int64_t s = 1'000'000'000;
  const std::vector<sim::RateMotion> motions{sim::hand_motion(6 * s, 60, s / 2, 1),
                                             sim::hand_motion(15 * s, 20, 2 * s, -1)};
  const auto trace = sim::simulate_gyro(sim::GyroConfig{}, motions, 0, 24 * s, 11, 0);
  const std::int64_t window = 500'000'000;
  GyroChannel channel("gyro", trace.clock, trace.counts_per_deg_s, {core::Duration{window}});
  std::vector<store::RateBlock> blocks;
  std::vector<store::Loss> losses;
  std::size_t at = 0;
  for (std::int64_t round_end = s / 10; at < trace.samples.size(); round_end += s / 10) {
    std::vector<core::RateSample> part;
    while (at < trace.samples.size() && trace.samples[at].time_ns < round_end)
      part.push_back(trace.samples[at++]);
    channel.add(std::move(part), {});
    channel.collect({1, rt(0), {}, at == trace.samples.size()}, rt(round_end), blocks, losses);
  }
  EXPECT_TRUE(losses.empty());
  EXPECT_EQ(channel.counters().stored + channel.counters().left_out, trace.samples.size());

  // Sample number -> stored, from the blocks; stored samples are the trace's own.
  std::vector<bool> stored(trace.samples.size(), false);
  for (const auto& b : blocks)
    for (std::size_t k = 0; k < b.samples.size(); ++k) {
      const auto n = b.first_index + k;
      ASSERT_LT(n, trace.samples.size());
      EXPECT_FALSE(stored[n]) << "sample " << n << " stored twice";
      stored[n] = true;
      EXPECT_EQ(b.samples[k].time_ns, trace.samples[n].time_ns);
      EXPECT_EQ(b.samples[k].raw, trace.samples[n].raw);
    }
  for (std::size_t n = 0; n < trace.samples.size(); ++n) {
    const std::int64_t t = trace.samples[n].time_ns;
    bool inside = false, far = true;
    for (const auto& m : motions) {
      // The window is around the detected onset and end, a few ms from the true ones: 50 ms of slack.
      if (t >= m.onset_ns - window + 50'000'000 && t <= m.end_ns() + window - 50'000'000) inside = true;
      if (t >= m.onset_ns - window - s / 5 && t <= m.end_ns() + window + s / 5) far = false;
    }
    if (inside) {
      ASSERT_TRUE(stored[n]) << "sample " << n << " at " << t << " ns, inside a window, was left out";
    }
    if (far) {
      ASSERT_FALSE(stored[n]) << "sample " << n << " at " << t << " ns, far from every motion, was kept";
    }
  }
  EXPECT_GT(channel.counters().left_out, trace.samples.size() / 2);
}

}  // namespace
}  // namespace m2mlat::capture::gyro_channel_test
