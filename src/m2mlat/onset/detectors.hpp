// The onset detectors by name, behind one table of functions (as chrony keeps its reference-clock
// drivers): "reference" (the reference rig's fixed threshold, reference.hpp) and "flank" (the rest
// level and a fit of the flank, flank.hpp), each with its default options. A new detector is one
// file and one row.
#pragma once

#include <span>
#include <string_view>

#include "m2mlat/onset/motion.hpp"

namespace m2mlat::onset {

struct Detector {
  std::string_view name;
  std::string_view summary;  // one line, for help and reports
  Detection (*detect)(const core::RateTrace& trace);
};

std::span<const Detector> detectors();
// The detector named `name`; core::Error(usage) naming the known ones otherwise.
const Detector& detector(std::string_view name);

}  // namespace m2mlat::onset
