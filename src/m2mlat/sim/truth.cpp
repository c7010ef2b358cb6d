// Names of the truth's enumerations.
#include "m2mlat/sim/truth.hpp"

#include <array>

namespace m2mlat::sim {

std::string_view to_string(EdgeKind kind) {
  static constexpr std::array<std::string_view, 4> kNames{"pass", "bounce", "spurious", "release"};
  return kNames.at(static_cast<std::size_t>(kind));
}

}  // namespace m2mlat::sim
