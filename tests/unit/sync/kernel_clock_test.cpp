// The kernel clock state from struct timex (units: us, or ns with STA_NANO; freq in ppm * 2^16),
// and the real read-only calls on this machine.
#include "m2mlat/sync/kernel_clock.hpp"

#include <gtest/gtest.h>
#include <sys/timex.h>

#include <cerrno>
#include <nlohmann/json.hpp>

namespace m2mlat::sync {
namespace {

struct timex synchronised_timex() {
  struct timex tx {};
  tx.status = STA_PLL | STA_NANO;
  tx.offset = -1234;     // ns (STA_NANO)
  tx.maxerror = 16500;   // us
  tx.esterror = 3;       // us
  tx.freq = 65536 * 12;  // 12 ppm
  tx.tick = 10000;
  tx.tai = 37;
  return tx;
}

TEST(KernelClock, SynchronisedStateInNanoseconds) {
  const auto s = kernel_clock_state(synchronised_timex(), TIME_OK);
  EXPECT_TRUE(s.available);
  EXPECT_TRUE(s.synchronised);
  EXPECT_EQ(s.offset_ns, -1234);
  EXPECT_EQ(s.max_error_ns, 16'500'000);
  EXPECT_EQ(s.est_error_ns, 3'000);
  EXPECT_DOUBLE_EQ(s.rate_ppm(), 12.0);
  EXPECT_EQ(s.tai, 37);
  EXPECT_EQ(status_names(s.status), (std::vector<std::string>{"PLL", "NANO"}));
}

TEST(KernelClock, OffsetInMicrosecondsWithoutStaNanoAndTickAdjustment) {
  auto tx = synchronised_timex();
  tx.status = STA_PLL;
  tx.offset = -1234;  // us
  tx.tick = 10001;    // 1 us per 10 ms tick longer: +100 ppm
  tx.freq = -65536 / 2;
  const auto s = kernel_clock_state(tx, TIME_OK);
  EXPECT_EQ(s.offset_ns, -1'234'000);
  EXPECT_DOUBLE_EQ(s.rate_ppm(), 99.5);
}

TEST(KernelClock, UnsynchronisedByFlagOrState) {
  auto tx = synchronised_timex();
  tx.status |= STA_UNSYNC;
  EXPECT_FALSE(kernel_clock_state(tx, TIME_OK).synchronised);
  EXPECT_FALSE(kernel_clock_state(synchronised_timex(), TIME_ERROR).synchronised);
  EXPECT_EQ(state_name(TIME_ERROR), "TIME_ERROR");
  EXPECT_EQ(state_name(TIME_INS), "TIME_INS");
  EXPECT_EQ(state_name(42), "unknown");
}

TEST(KernelClock, FailedCallIsUnavailableWithTheReason) {
  const auto s = kernel_clock_state(synchronised_timex(), -1, EPERM);
  EXPECT_FALSE(s.available);
  EXPECT_FALSE(s.synchronised);
  EXPECT_NE(s.error.find("clock_adjtime"), std::string::npos);
  const auto sample = adjtimex_sample(s, {});
  EXPECT_FALSE(sample.synchronised);
  EXPECT_TRUE(nlohmann::json::parse(sample.detail_json).contains("error"));
}

TEST(KernelClock, SampleCarriesTheFields) {
  const auto time = core::TimePoint::from_ns(core::Clock::realtime, 1'700'000'000'000'000'000);
  const auto sample = adjtimex_sample(kernel_clock_state(synchronised_timex(), TIME_OK), time);
  EXPECT_EQ(sample.source, "adjtimex");
  EXPECT_EQ(sample.time, time);
  EXPECT_EQ(sample.offset_ns, -1234);
  EXPECT_EQ(sample.max_error_ns, 16'500'000);
  EXPECT_EQ(sample.est_error_ns, 3'000);
  EXPECT_TRUE(sample.synchronised);
  const auto d = nlohmann::json::parse(sample.detail_json);
  EXPECT_EQ(d["state"], "TIME_OK");
  EXPECT_EQ(d["status_bits"], nlohmann::json({"PLL", "NANO"}));
  EXPECT_DOUBLE_EQ(d["freq_ppm"].get<double>(), 12.0);
  EXPECT_EQ(d["tai_s"], 37);
}

TEST(KernelClock, RealReadOnlyCallsWork) {
  const auto s = read_kernel_clock();
  EXPECT_TRUE(s.available) << s.error;
  EXPECT_GE(s.max_error_ns, 0);
  const auto a = read_clock_pair();
  const auto b = read_clock_pair();
  EXPECT_GT(a.realtime_ns, 1'600'000'000LL * 1'000'000'000);
  EXPECT_GE(b.monotonic_raw_ns, a.monotonic_raw_ns);
  EXPECT_GE(a.window_ns, 0);
  EXPECT_LT(a.window_ns, 10'000'000);  // 10 ms even on a loaded CI machine
}

}  // namespace
}  // namespace m2mlat::sync
