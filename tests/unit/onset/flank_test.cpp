// The flank detector on hand-made traces: the onset and end of a linear and of a smooth start found
// back at the rest level, with an uncertainty that covers the error; nothing in noise or under the
// peak floor; two motions; a trace that begins in a motion; bad input.
#include "m2mlat/onset/flank.hpp"

#include <gtest/gtest.h>

#include "m2mlat/core/error.hpp"
#include "m2mlat/onset/detectors.hpp"
#include "m2mlat/onset/reference.hpp"
#include "trace_util.hpp"

namespace m2mlat::onset {
namespace {

using test::kMs;
using test::kPeriod;

// A smooth rotation: rate = A/T 30 s^2 (1 - s)^2 (minimum jerk) between t0 and t0 + T.
std::function<double(std::int64_t)> smooth(std::int64_t t0, double peak, std::int64_t duration) {
  return [=](std::int64_t t) {
    const double s = static_cast<double>(t - t0) / static_cast<double>(duration);
    return s <= 0 || s >= 1 ? 0.0 : peak / 1.875 * 30 * s * s * (1 - s) * (1 - s);
  };
}

TEST(Flank, LinearStartFoundAtTheRestLevel) {
  // 2000 deg/s^2 (an actuator's torque step) to 200 deg/s: it crosses 25 deg/s 12.5 ms after t0.
  const std::int64_t t0 = 600 * kMs + 37'000;
  const auto trace = test::make_trace(2000 * kMs, test::ramp(t0, 2000, 200, 300 * kMs));
  const auto d = detect_flank(trace);
  ASSERT_EQ(d.motions.size(), 1u);
  const auto& m = d.motions[0];
  EXPECT_LT(std::llabs(m.onset_ns - t0), 100'000) << m.onset_ns - t0;
  const std::int64_t end = t0 + 2 * 100 * kMs + 300 * kMs;
  EXPECT_LT(std::llabs(m.end_ns - end), 100'000) << m.end_ns - end;
  EXPECT_TRUE(m.ended);
  EXPECT_NEAR(m.peak_deg_s, 200, 2);
  // The stated uncertainty is the fit's and the stamps' (60 us / sqrt(3) = 35 us at least), and
  // covers the error.
  EXPECT_GE(m.onset_sd_ns, 34'000);
  EXPECT_LE(std::llabs(m.onset_ns - t0), 4 * m.onset_sd_ns);
  // The fixed threshold lags the same motion by 12.5 ms and more.
  const auto r = detect_reference(trace);
  ASSERT_EQ(r.motions.size(), 1u);
  EXPECT_GT(r.motions[0].onset_ns - t0, 12 * kMs);
}

TEST(Flank, SmoothStartsOfSeveralSpeedsAreFoundWithoutARateDependentLag) {
  for (const double peak : {30.0, 100.0, 300.0}) {
    const std::int64_t t0 = 500 * kMs + 11'000;
    const auto d = detect_flank(test::make_trace(2000 * kMs, smooth(t0, peak, 800 * kMs), 0.1, 7));
    ASSERT_EQ(d.motions.size(), 1u) << peak;
    const auto& m = d.motions[0];
    EXPECT_LE(std::llabs(m.onset_ns - t0), std::max<std::int64_t>(4 * m.onset_sd_ns, 200'000))
        << peak << " deg/s: error " << m.onset_ns - t0 << " ns, sd " << m.onset_sd_ns;
    EXPECT_LT(std::llabs(m.onset_ns - t0), 2 * kMs) << peak;
    EXPECT_LT(std::llabs(m.end_ns - (t0 + 800 * kMs)), 2 * kMs) << peak;
  }
}

TEST(Flank, NoiseAndBumpsAreNoMotion) {
  EXPECT_TRUE(detect_flank(test::make_trace(5000 * kMs, [](std::int64_t) { return 0.0; })).motions.empty());
  // A 3 deg/s knock (under min_peak_deg_s) is a bump.
  EXPECT_TRUE(detect_flank(test::make_trace(2000 * kMs, smooth(500 * kMs, 3, 100 * kMs))).motions.empty());
}

TEST(Flank, TwoMotionsEachWithItsOnset) {
  const std::int64_t a = 400 * kMs, b = 1400 * kMs;
  const auto d = detect_flank(test::make_trace(2500 * kMs, [&](std::int64_t t) {
    return smooth(a, 150, 500 * kMs)(t) - smooth(b, 80, 600 * kMs)(t);
  }));
  ASSERT_EQ(d.motions.size(), 2u);
  EXPECT_LT(std::llabs(d.motions[0].onset_ns - a), kMs);
  EXPECT_LT(std::llabs(d.motions[1].onset_ns - b), kMs);  // turning the other way
}

TEST(Flank, ATraceBeginningInAMotionReportsOnlyTheLaterOnes) {
  const std::int64_t later = 1500 * kMs;
  const auto d = detect_flank(test::make_trace(2500 * kMs, [&](std::int64_t t) {
    return (t < 300 * kMs ? 90.0 : 0.0) + smooth(later, 120, 600 * kMs)(t);
  }));
  EXPECT_TRUE(d.began_in_motion);
  ASSERT_EQ(d.motions.size(), 1u);
  EXPECT_LT(std::llabs(d.motions[0].onset_ns - later), kMs);
}

TEST(Flank, AMotionAtTheTraceEndIsOpen) {
  const auto d = detect_flank(test::make_trace(900 * kMs, smooth(500 * kMs, 100, 800 * kMs)));
  ASSERT_EQ(d.motions.size(), 1u);
  EXPECT_FALSE(d.motions[0].ended);
  EXPECT_LT(std::llabs(d.motions[0].onset_ns - 500 * kMs), kMs);
}

TEST(Flank, EmptyAndShortTracesHaveNoMotion) {
  core::RateTrace empty;
  EXPECT_TRUE(detect_flank(empty).motions.empty());
  EXPECT_TRUE(detect_flank(test::make_trace(50 * kMs, smooth(0, 100, 40 * kMs))).motions.empty());
}

TEST(Detectors, BadTracesAreRefusedNamingWhatIsWrong) {
  auto trace = test::make_trace(10 * kPeriod, [](std::int64_t) { return 0.0; });
  std::swap(trace.samples[3], trace.samples[4]);
  for (const auto& d : detectors()) {
    try {
      d.detect(trace);
      FAIL() << d.name;
    } catch (const core::Error& e) {
      EXPECT_EQ(e.kind(), core::ErrorKind::data);
      EXPECT_NE(std::string(e.what()).find("sample 4"), std::string::npos) << e.what();
    }
  }
  trace = test::make_trace(10 * kPeriod, [](std::int64_t) { return 0.0; });
  trace.counts_per_deg_s = 0;
  for (const auto& d : detectors()) {
    try {
      d.detect(trace);
      FAIL() << d.name;
    } catch (const core::Error& e) {
      EXPECT_EQ(e.kind(), core::ErrorKind::data);
      EXPECT_NE(std::string(e.what()).find("counts_per_deg_s"), std::string::npos) << e.what();
    }
  }
  trace.counts_per_deg_s = 131;
  trace.samples[2].bound_ns = -1;
  EXPECT_THROW(detect_flank(trace), core::Error);
}

TEST(Detectors, ChosenByName) {
  EXPECT_EQ(detector("reference").name, "reference");
  EXPECT_EQ(detector("flank").name, "flank");
  try {
    detector("magic");
    FAIL();
  } catch (const core::Error& e) {
    EXPECT_EQ(e.kind(), core::ErrorKind::usage);
    EXPECT_NE(std::string(e.what()).find("reference, flank"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace m2mlat::onset
