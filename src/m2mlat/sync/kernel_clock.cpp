// Reading the kernel clock discipline (clock_adjtime, read-only) and the realtime/raw clock pair.
#include "m2mlat/sync/kernel_clock.hpp"

#include "m2mlat/core/clock_read.hpp"

#include <sys/timex.h>
#include <time.h>

#include <cerrno>
#include <cstring>
#include <nlohmann/json.hpp>
#include <utility>

namespace m2mlat::sync {

namespace {

constexpr std::pair<int, const char*> kStatusBits[] = {
    {STA_PLL, "PLL"},
    {STA_PPSFREQ, "PPSFREQ"},
    {STA_PPSTIME, "PPSTIME"},
    {STA_FLL, "FLL"},
    {STA_INS, "INS"},
    {STA_DEL, "DEL"},
    {STA_UNSYNC, "UNSYNC"},
    {STA_FREQHOLD, "FREQHOLD"},
    {STA_PPSSIGNAL, "PPSSIGNAL"},
    {STA_PPSJITTER, "PPSJITTER"},
    {STA_PPSWANDER, "PPSWANDER"},
    {STA_PPSERROR, "PPSERROR"},
    {STA_CLOCKERR, "CLOCKERR"},
    {STA_NANO, "NANO"},
    {STA_MODE, "MODE"},
    {STA_CLK, "CLK"},
};

}  // namespace

double KernelClockState::rate_ppm() const {
  return static_cast<double>(freq_scaled) / 65536.0 + static_cast<double>(tick_us - 10000) * 100.0;
}

KernelClockState kernel_clock_state(const struct timex& tx, int rc, int error_number) {
  KernelClockState s;
  if (rc < 0) {
    s.error = std::string("clock_adjtime: ") + std::strerror(error_number);
    return s;
  }
  s.available = true;
  s.state = rc;
  s.status = tx.status;
  s.synchronised = (tx.status & STA_UNSYNC) == 0 && rc != TIME_ERROR;
  s.offset_ns = (tx.status & STA_NANO) ? std::int64_t{tx.offset} : std::int64_t{tx.offset} * 1000;
  s.max_error_ns = std::int64_t{tx.maxerror} * 1000;
  s.est_error_ns = std::int64_t{tx.esterror} * 1000;
  s.freq_scaled = tx.freq;
  s.tick_us = tx.tick;
  s.tai = tx.tai;
  return s;
}

KernelClockState read_kernel_clock() {
  struct timex tx {};
  tx.modes = 0;  // read only
  const int rc = ::clock_adjtime(CLOCK_REALTIME, &tx);
  return kernel_clock_state(tx, rc, rc < 0 ? errno : 0);
}

std::vector<std::string> status_names(int status) {
  std::vector<std::string> names;
  for (const auto& [bit, name] : kStatusBits)
    if (status & bit) names.emplace_back(name);
  return names;
}

std::string state_name(int state) {
  switch (state) {
    case TIME_OK: return "TIME_OK";
    case TIME_INS: return "TIME_INS";
    case TIME_DEL: return "TIME_DEL";
    case TIME_OOP: return "TIME_OOP";
    case TIME_WAIT: return "TIME_WAIT";
    case TIME_ERROR: return "TIME_ERROR";
    default: return "unknown";
  }
}

store::ClockSample adjtimex_sample(const KernelClockState& state, core::TimePoint time) {
  store::ClockSample sample;
  sample.time = time;
  sample.source = "adjtimex";
  sample.offset_ns = state.offset_ns;
  sample.max_error_ns = state.max_error_ns;
  sample.est_error_ns = state.est_error_ns;
  sample.synchronised = state.synchronised;
  nlohmann::json detail{{"state", state_name(state.state)},
                        {"status", state.status},
                        {"status_bits", status_names(state.status)},
                        {"freq_ppm", static_cast<double>(state.freq_scaled) / 65536.0},
                        {"tick_us", state.tick_us},
                        {"tai_s", state.tai}};
  if (!state.available) detail = {{"error", state.error}};
  sample.detail_json = detail.dump();
  return sample;
}

ClockPair read_clock_pair() {
  // Retry a few times when the reads were far apart (preempted between them): take the tightest.
  ClockPair best;
  best.window_ns = INT64_MAX;
  for (int attempt = 0; attempt < 4; ++attempt) {
    const std::int64_t raw0 = core::now_ns(CLOCK_MONOTONIC_RAW);
    const std::int64_t real = core::now_ns(CLOCK_REALTIME);
    const std::int64_t raw1 = core::now_ns(CLOCK_MONOTONIC_RAW);
    if (raw1 - raw0 < best.window_ns) best = {real, raw0 + (raw1 - raw0) / 2, raw1 - raw0};
    if (best.window_ns < 20'000) break;  // 20 us: good enough against a 1 ms step threshold
  }
  return best;
}

}  // namespace m2mlat::sync
