// The synchronisation test: statistics, jitter and metrics of paired pulses; the daemons' view; and
// the reference rig's published one-hour tests when they are beside the checkout.
#include "m2mlat/selftest/synctest.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>

#include "m2mlat/formats/rig_sync.hpp"

namespace m2mlat::selftest {
namespace {

constexpr std::int64_t kT0 = 1'762'872'545'000'000'000;
constexpr std::int64_t kPeriod = 500'000'000;

TEST(SyncTest, ValueStatsByHand) {
  const std::vector<std::int64_t> v{-3, 1, 2, 8};
  const std::vector<double> percents{50};
  const auto s = value_stats(v, percents);
  EXPECT_EQ(s.n, 4u);
  EXPECT_DOUBLE_EQ(s.mean_ns, 2.0);
  EXPECT_DOUBLE_EQ(s.sd_ns, std::sqrt((25.0 + 1 + 0 + 36) / 3));
  EXPECT_DOUBLE_EQ(s.min_ns, -3);
  EXPECT_DOUBLE_EQ(s.max_ns, 8);
  EXPECT_DOUBLE_EQ(s.percentiles.at(0).second, 1.5);
  EXPECT_TRUE(std::isnan(value_stats(std::vector<std::int64_t>{}, percents).mean_ns));
}

TEST(SyncTest, EdgesWithLossesAndTheDaemonsView) {
  // B reads 300 us ahead of A, plus white noise of 20 us; 3 pulses lost on A, 2 on B, 1 glitch on B.
  std::mt19937_64 rng(3);
  std::normal_distribution<double> noise(0, 20'000);
  std::vector<std::int64_t> a, b;
  std::vector<std::int64_t> offsets;
  for (int i = 0; i < 1000; ++i) {
    const std::int64_t ta = kT0 + i * kPeriod;
    const std::int64_t off = 300'000 + static_cast<std::int64_t>(noise(rng));
    const bool lose_a = i == 10 || i == 500 || i == 501, lose_b = i == 20 || i == 900;
    if (!lose_a) a.push_back(ta);
    if (!lose_b) b.push_back(ta + off);
    if (!lose_a && !lose_b) offsets.push_back(off);
  }
  b.push_back(kT0 + 300 * kPeriod + 200'000'000);
  // The daemons: A thinks it is 10 us ahead, B 250 us ahead; each bounds itself by 100 us.
  std::vector<store::ClockSample> ca, cb;
  for (int k = 0; k <= 50; ++k) {
    store::ClockSample s;
    s.time = core::TimePoint::from_ns(core::Clock::realtime, kT0 + k * 10 * 1'000'000'000LL);
    s.source = "chrony";
    s.synchronised = true;
    s.max_error_ns = 100'000;
    s.offset_ns = 10'000;
    ca.push_back(s);
    s.offset_ns = 250'000;
    cb.push_back(s);
  }
  const auto r =
      synctest_from_edges(a, b, analysis::make_clock_track(ca), analysis::make_clock_track(cb), {}, {},
                          /*growth_ppm=*/0);
  EXPECT_EQ(r.period.count(), kPeriod);
  ASSERT_EQ(r.series.size(), offsets.size());
  EXPECT_EQ(r.unmatched_a, 2u);
  EXPECT_EQ(r.unmatched_b, 4u);  // the partners of A's 3 losses, and the glitch
  EXPECT_EQ(r.gaps, 4u);         // pulses 10, 20, 500-501, 900: intervals longer than 1.5 tau0
  long double sum = 0;
  for (auto o : offsets) sum += static_cast<long double>(o);
  EXPECT_NEAR(r.offset.mean_ns, static_cast<double>(sum / static_cast<long double>(offsets.size())), 1e-6);
  EXPECT_NEAR(r.offset.sd_ns, 20'000, 1'500);
  // White phase noise: TDEV(tau0) is the sd; the jitter's sd is sqrt(2) times it.
  ASSERT_FALSE(r.stability.empty());
  EXPECT_EQ(r.stability.front().n, 1u);
  EXPECT_DOUBLE_EQ(r.stability.front().tau_s, 0.5);
  EXPECT_NEAR(r.stability.front().tdev_ns, 20'000, 1'500);
  EXPECT_NEAR(r.jitter.sd_ns, std::sqrt(2.0) * 20'000, 2'500);
  EXPECT_EQ(r.jitter.n, r.series.size() - 1);
  // The daemons estimate 240 us where 300 us is measured, and their bound of 200 us is exceeded.
  EXPECT_EQ(r.daemon_samples, r.series.size());
  EXPECT_NEAR(r.daemon_error.mean_ns, 60'000, 2'000);
  EXPECT_LT(r.within_daemon_bound, r.series.size() / 10);

  const auto j = synctest_json(r, true);
  EXPECT_EQ(j["format"], "m2mlat-synctest/1");
  EXPECT_EQ(j["series"].size(), r.series.size());
  EXPECT_EQ(j["offset"]["n"], r.series.size());
  std::ostringstream csv;
  write_series_csv(csv, r);
  EXPECT_EQ(csv.str().substr(0, 45), "t_ns,offset_ns,daemon_offset_ns,daemon_bound_");
}

// The reference rig's one-hour tests (pulse every ~1.07 s to both boards), when present.
std::filesystem::path upstream_dir() {
  return std::filesystem::path(M2MLAT_TEST_DATA) / ".." / ".." / ".." / "shared" / "data" /
         "upstream-results";
}

TEST(SyncTest, ReferenceRigTables) {
  for (const char* name : {"Co_Referenced.csv", "Autonomous.csv"}) {
    const auto path = upstream_dir() / name;
    if (!std::filesystem::exists(path)) GTEST_SKIP() << "no reference data at " << path;
    std::ifstream in(path);
    std::stringstream text;
    text << in.rdbuf();
    const auto rig = formats::import_rig_sync_csv(text.str(), path.string());
    const auto r = synctest_from_rig(rig);
    ASSERT_EQ(r.series.size(), rig.samples.size());
    EXPECT_EQ(r.offset.n, 3599u);
    // Recomputed here from the rows, independently of value_stats: count, mean, sd, min, max of the
    // offsets and of their magnitudes (the study's sync_offset_ms column).
    double sum = 0, abs_sum = 0, mn = 1e300, mx = -1e300, abs_mn = 1e300, abs_mx = 0;
    for (const auto& s : rig.samples) {
      const double v = static_cast<double>(s.offset_ns), a = std::abs(v);
      sum += v, abs_sum += a, mn = std::min(mn, v), mx = std::max(mx, v);
      abs_mn = std::min(abs_mn, a), abs_mx = std::max(abs_mx, a);
    }
    const double n = static_cast<double>(rig.samples.size());
    double ss = 0, abs_ss = 0;
    for (const auto& s : rig.samples) {
      const double v = static_cast<double>(s.offset_ns), a = std::abs(v);
      ss += (v - sum / n) * (v - sum / n);
      abs_ss += (a - abs_sum / n) * (a - abs_sum / n);
    }
    EXPECT_NEAR(r.offset.mean_ns, sum / n, 1e-3);
    EXPECT_NEAR(r.offset.sd_ns, std::sqrt(ss / (n - 1)), 1e-3);
    EXPECT_EQ(r.offset.min_ns, mn);
    EXPECT_EQ(r.offset.max_ns, mx);
    EXPECT_NEAR(r.abs_offset.mean_ns, abs_sum / n, 1e-3);
    EXPECT_NEAR(r.abs_offset.sd_ns, std::sqrt(abs_ss / (n - 1)), 1e-3);
    EXPECT_EQ(r.abs_offset.min_ns, abs_mn);
    EXPECT_EQ(r.abs_offset.max_ns, abs_mx);
    // The study's summary: about 0.3 ms mean offset between the boards in both set-ups.
    EXPECT_NEAR(r.abs_offset.mean_ns / 1e6, 0.3, 0.05) << name;
    // The rig's own Jitter_ns column is the successive difference (where its rows are consistent).
    std::size_t same = 0;
    for (std::size_t i = 1; i < rig.samples.size(); ++i)
      same += rig.samples[i].jitter_ns == rig.samples[i].offset_ns - rig.samples[i - 1].offset_ns;
    EXPECT_EQ(r.jitter.n, rig.samples.size() - 1);
    EXPECT_GT(same, 0u);
    // Sampled about every 1.07 s; metrics up to an hour/3.
    EXPECT_GT(r.tau0.count(), 1'000'000'000);
    EXPECT_LT(r.tau0.count(), 1'200'000'000);
    EXPECT_GE(r.stability.size(), 10u);
  }
}

}  // namespace
}  // namespace m2mlat::selftest
