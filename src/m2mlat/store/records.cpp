// Names of durability policies.
#include "m2mlat/store/records.hpp"

#include <fmt/format.h>

#include "m2mlat/core/error.hpp"

namespace m2mlat::store {

std::string_view to_string(Durability durability) {
  switch (durability) {
    case Durability::full: return "full";
    case Durability::normal: return "normal";
    case Durability::off: return "off";
  }
  return "normal";
}

Durability parse_durability(std::string_view text) {
  if (text == "full") return Durability::full;
  if (text == "normal") return Durability::normal;
  if (text == "off") return Durability::off;
  throw core::Error(core::ErrorKind::usage,
                    fmt::format("unknown durability '{}' (expected full, normal or off)", text));
}

}  // namespace m2mlat::store
