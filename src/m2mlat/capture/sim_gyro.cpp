// The simulated gyroscope's motion pattern and its register twin (sim_gyro.hpp).
#include "m2mlat/capture/sim_gyro.hpp"

#include <algorithm>
#include <cmath>

#include "m2mlat/capture/mpu6050.hpp"
#include "m2mlat/core/clock_read.hpp"
#include "m2mlat/core/random.hpp"
#include "m2mlat/sim/gyro_motion.hpp"

namespace m2mlat::capture {

namespace {

// The rotation of interval number k (onset at k * interval + offset).
sim::RateMotion sim_gyro_motion(std::int64_t k) {
  return sim::hand_motion(k * kSimGyroInterval.count() + kSimGyroOffset.count(), kSimGyroPeakDegS,
                          kSimGyroDuration.count(), k % 2 == 0 ? 1 : -1);
}

std::int64_t sim_gyro_interval_of(std::int64_t t_ns) {
  const std::int64_t i = kSimGyroInterval.count();
  return t_ns >= 0 ? t_ns / i : (t_ns - i + 1) / i;
}

}  // namespace

double sim_gyro_rate_deg_s(std::int64_t t_ns) { return sim::rate_deg_s(sim_gyro_motion(sim_gyro_interval_of(t_ns)), t_ns); }

std::int64_t sim_gyro_next_onset(std::int64_t t_ns) {
  const auto m = sim_gyro_motion(sim_gyro_interval_of(t_ns));
  return t_ns < m.end_ns() ? m.onset_ns : sim_gyro_motion(sim_gyro_interval_of(t_ns) + 1).onset_ns;
}

std::unique_ptr<RegisterTwin> make_sim_gyro(std::uint64_t seed) {
  auto twin = std::make_unique<RegisterTwin>();
  twin->registers[mpu6050::reg::who_am_i] = 0x68;
  std::uint64_t state = seed;
  core::Xoshiro256 rng({core::splitmix64(state), core::splitmix64(state), core::splitmix64(state),
                        core::splitmix64(state)});
  RegisterTwin* t = twin.get();
  twin->before_read = [t, rng]() mutable {
    const auto noise = [&] { return static_cast<int>(rng.next() % 5) - 2; };  // -2..+2 counts
    const double counts = sim_gyro_rate_deg_s(core::realtime_now().ns()) * mpu6050::kCountsPerDegS;
    const auto clip = [](double c) { return static_cast<std::int16_t>(std::clamp(std::lround(c), -32768L, 32767L)); };
    t->set_rates(clip(counts + noise()), clip(noise()), clip(noise()));
  };
  return twin;
}

}  // namespace m2mlat::capture
