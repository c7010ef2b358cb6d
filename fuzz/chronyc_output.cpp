// Fuzzes the reader of `chronyc -c tracking sources` (sync/chrony.hpp) as the clock monitor meets it:
// any bytes either parse into a report whose clock sample has a non-negative bound, or are refused
// with core::Error(data); never another exception, a crash or a signed overflow.
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string_view>

#include "m2mlat/core/error.hpp"
#include "m2mlat/sync/chrony.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace m2mlat;
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  try {
    const auto report = sync::parse_chronyc_output(text, core::Location{"fuzz", 0});
    const auto sample = sync::chrony_sample(report, core::TimePoint::from_ns(core::Clock::realtime, 0));
    if (sample.max_error_ns < 0 || sample.est_error_ns < 0) std::abort();
  } catch (const core::Error& e) {
    if (e.kind() != core::ErrorKind::data) std::abort();
  }
  return 0;
}
