// Names of sides and unmatched reasons.
#include "m2mlat/pairing/pair.hpp"

namespace m2mlat::pairing {

std::string_view to_string(Side side) { return side == Side::cause ? "cause" : "effect"; }

std::string_view to_string(UnmatchedReason reason) {
  switch (reason) {
    case UnmatchedReason::bounce: return "bounce";
    case UnmatchedReason::no_candidate: return "no_candidate";
    case UnmatchedReason::outmatched: return "outmatched";
  }
  return "no_candidate";
}

}  // namespace m2mlat::pairing
