#include "m2mlat/onset/detectors.hpp"

#include <fmt/format.h>

#include <array>

#include "m2mlat/core/error.hpp"
#include "m2mlat/onset/flank.hpp"
#include "m2mlat/onset/reference.hpp"

namespace m2mlat::onset {

namespace {
Detection run_reference(const core::RateTrace& trace) { return detect_reference(trace); }
Detection run_flank(const core::RateTrace& trace) { return detect_flank(trace); }

constexpr std::array kDetectors{
    Detector{"reference", "the reference rig's: EMA alpha 0.05 per axis, magnitude above 25 deg/s",
             &run_reference},
    Detector{"flank",
             "rest level and noise learned, threshold k x noise, hinge fit of the flank to the rest level",
             &run_flank},
};
}  // namespace

std::span<const Detector> detectors() { return kDetectors; }

const Detector& detector(std::string_view name) {
  for (const auto& d : kDetectors)
    if (d.name == name) return d;
  std::string known;
  for (const auto& d : kDetectors) known += (known.empty() ? "" : ", ") + std::string(d.name);
  throw core::Error(core::ErrorKind::usage, fmt::format("no onset detector '{}' (known: {})", name, known));
}

}  // namespace m2mlat::onset
