// Colours from the scenarios' names.
#include "m2mlat/report/scenario_colours.hpp"

#include <array>
#include <cstdint>

namespace m2mlat::report {

std::vector<std::size_t> scenario_colours(std::span<const std::string> names) {
  constexpr std::size_t kColours = 8;
  std::array<bool, kColours> taken{};
  std::size_t used = 0;
  std::vector<std::size_t> out;
  for (const auto& name : names) {
    std::uint64_t h = 14695981039346656037ull;  // FNV-1a, 64 bits
    for (const char ch : name) h = (h ^ static_cast<unsigned char>(ch)) * 1099511628211ull;
    std::size_t k = static_cast<std::size_t>(h % kColours);
    if (used == kColours) taken.fill(false), used = 0;
    while (taken[k]) k = (k + 1) % kColours;
    taken[k] = true;
    ++used;
    out.push_back(k);
  }
  return out;
}

}  // namespace m2mlat::report
