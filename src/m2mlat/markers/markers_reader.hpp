// Reading `m2mlat-markers/1` CSV files back (docs/formats.md): the markers `m2mlat packets --csv`,
// `m2mlat simulate --markers` and other tools write, for the stage breakdown (`stats --markers`).
// The writer is markers_file.hpp.
#pragma once

#include <string>
#include <string_view>
#include <vector>

#include "m2mlat/markers/marker.hpp"

namespace m2mlat::markers {

// The markers of one file's text, in file order. Throws core::Error(data) naming the file, the line
// and the field of the first bad row (nothing is returned then).
std::vector<Marker> parse_markers_csv(std::string_view text, std::string_view name);
// Reads a file ("-" standard input); core::Error(no_input) when it does not exist.
std::vector<Marker> read_markers_file(const std::string& path);

}  // namespace m2mlat::markers
