// A simulated gyroscope on the register twin (register_twin.hpp), for running `record --gyro sim`
// and `agent --gyro sim` without a chip: the same driver, sampler and channel read it as they read a
// real MPU-6050, and before each read its rate registers are set from a fixed pattern of hand
// motions on CLOCK_REALTIME, so that the true onsets are known from the clock alone.
//
// The pattern: a minimum-jerk rotation (sim/gyro_motion.hpp) of kSimGyroDuration, peaking at
// kSimGyroPeakDegS, every kSimGyroInterval, beginning kSimGyroOffset after every whole multiple of
// the interval since the Unix epoch, turning alternately one way and the other; plus a uniform
// noise of +-2 counts (about +-0.015 deg/s) so that a detector's rest level has a spread.
#pragma once

#include <cstdint>
#include <memory>

#include "m2mlat/capture/register_twin.hpp"
#include "m2mlat/core/time.hpp"

namespace m2mlat::capture {

inline constexpr core::Duration kSimGyroInterval{2'000'000'000};  // between two onsets, ns
inline constexpr core::Duration kSimGyroOffset{500'000'000};      // onset after each whole interval, ns
inline constexpr core::Duration kSimGyroDuration{500'000'000};    // each rotation's length, ns
inline constexpr double kSimGyroPeakDegS = 60;                    // each rotation's peak rate, deg/s

// The simulated true rate at CLOCK_REALTIME t, deg/s.
double sim_gyro_rate_deg_s(std::int64_t t_ns);
// The true onset of the simulated rotation that is going on or comes next at CLOCK_REALTIME t, ns.
std::int64_t sim_gyro_next_onset(std::int64_t t_ns);

// A register twin answering as an MPU-6050 whose rate registers follow the pattern above (x the
// rotation axis, y and z noise only).
std::unique_ptr<RegisterTwin> make_sim_gyro(std::uint64_t seed);

}  // namespace m2mlat::capture
