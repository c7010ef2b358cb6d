// The report as one self-contained HTML page: inline CSS and inline SVG charts, no script, no
// external resource, so it works offline, reads on a phone (fluid SVGs, scrolling tables) and prints
// (each figure kept on one page). Charts carry data-chart="..." so tests can find them:
//   box (per-scenario box plots, grouped), ecdf, histogram, timeseries-<n> (latency over time with
//   per-sample uncertainty bars, per scenario n = 0, 1, ...), clock-<n> (clock offset and error bound
//   per board, where the store has clock samples), budget (the error budget, when known).
#pragma once

#include <string>

#include "m2mlat/report/report_model.hpp"

namespace m2mlat::report {

std::string report_html(const Report& report);

}  // namespace m2mlat::report
