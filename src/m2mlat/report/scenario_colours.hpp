// Each scenario's colour, the same in every figure and every report: a reader who has seen static_5g in
// orange finds it in orange in the next report too, whatever other scenarios it holds.
#pragma once

#include <cstddef>
#include <span>
#include <string>
#include <vector>

namespace m2mlat::report {

// The palette index (svg_plot.hpp's palette, pgfplots' colours: 8 of them) of each name: FNV-1a of the
// name modulo 8, and for a name whose colour an earlier name of the list took, the next free one (the
// same for every list with the same earlier names; a ninth name shares again).
std::vector<std::size_t> scenario_colours(std::span<const std::string> names);

}  // namespace m2mlat::report
