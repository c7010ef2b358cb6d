// Fuzzes the readers of cyclictest's output (selftest/cyclictest.hpp) as `m2mlat schedtest` meets
// them: the first byte chooses the JSON summary or the histogram text, the rest is the input. Either
// a result comes back (min <= max for every thread that ran) or core::Error(data); never another exception.
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string_view>

#include "m2mlat/core/error.hpp"
#include "m2mlat/selftest/cyclictest.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace m2mlat;
  if (size < 1) return 0;
  const std::string_view text(reinterpret_cast<const char*>(data + 1), size - 1);
  const core::Location where{"fuzz", 0};
  try {
    if (data[0] % 2 == 0) {
      const auto result = selftest::parse_cyclictest_json(text, where);
      for (const auto& t : result.threads)
        if (t.cycles > 0 && t.min_us > t.max_us) std::abort();
    } else {
      const auto histogram = selftest::parse_cyclictest_histogram(text, where);
      if (histogram.total.size() != histogram.counts.size()) std::abort();
    }
  } catch (const core::Error& e) {
    if (e.kind() != core::ErrorKind::data) std::abort();
  }
  return 0;
}
