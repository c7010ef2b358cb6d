// Fuzzes the reader of linuxptp's `pmc` output (sync/ptp.hpp) as the clock monitor meets it: any bytes
// either give responses (and, where both management ids are there, a status whose clock sample has a
// non-negative bound) or are refused with core::Error(data); never another exception or a crash.
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string_view>

#include "m2mlat/core/error.hpp"
#include "m2mlat/sync/ptp.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace m2mlat;
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  const core::Location where{"fuzz", 0};
  try {
    const auto responses = sync::parse_pmc_output(text, where);
    const auto status = sync::ptp_status(responses, where);
    const auto sample = sync::ptp_sample(status, core::TimePoint::from_ns(core::Clock::realtime, 0));
    if (sample.max_error_ns < 0 || sample.est_error_ns < 0) std::abort();
  } catch (const core::Error& e) {
    if (e.kind() != core::ErrorKind::data) std::abort();
  }
  return 0;
}
