// Whole-text numbers (number.hpp).
#include "m2mlat/core/number.hpp"

namespace m2mlat::core {

bool parse_double(std::string_view text, double& value) {
  if (!text.empty() && text.front() == '+') {
    text.remove_prefix(1);
    if (!text.empty() && text.front() == '-') return false;  // "+-1": one sign only
  }
  if (text.empty()) return false;
  double parsed = 0;
  const char* end = text.data() + text.size();
  const auto [ptr, ec] = std::from_chars(text.data(), end, parsed);
  if (ec != std::errc{} || ptr != end) return false;
  value = parsed;
  return true;
}

}  // namespace m2mlat::core
