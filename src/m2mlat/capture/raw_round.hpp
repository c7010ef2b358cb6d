// One round of raw samples (a gyroscope's) handed to the recorder: which session the samples of
// the round belong to. A sample belongs to the session it was sampled in: stamped at or after the
// session's start and, when the session ends, at or before its end. The recorder asks every commit
// round, once more when a session ends (with the end time: a block never crosses it) and once after
// the stop; while no session is open it asks too, so that what is sampled then is let go (it belongs
// to no session) instead of piling up.
#pragma once

#include <cstdint>
#include <optional>

#include "m2mlat/core/time.hpp"

namespace m2mlat::capture {

struct RawRound {
  std::int64_t session_id = 0;        // the open session; 0: none is open
  core::TimePoint session_start;      // its start (CLOCK_REALTIME): samples stamped earlier are not its
  std::optional<core::TimePoint> end;  // set: the session ends at this time; samples stamped up to it
                                       // are decided now, later ones wait for the next session
  bool final = false;                  // the recorder has stopped and so has the sampler: decide all
};

}  // namespace m2mlat::capture
