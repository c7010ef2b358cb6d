// The full-loop rig's files shown: M2M, G2G and E2E (and each side's motion duration) side by side,
// one row per file and quantity, with the events left out of each quantity counted by reason. As
// a terminal table, JSON (the "full_loop" member of m2mlat-stats/1 and m2mlat-report/1), and the boxes of the
// figure the HTML report (data-chart="full-loop") and the pgfplots files (full-loop.tex) draw: the
// distributions of each file's M2M, G2G and E2E beside each other.
#pragma once

#include <nlohmann/json.hpp>
#include <span>
#include <string>
#include <vector>

#include "m2mlat/analysis/full_loop.hpp"
#include "m2mlat/report/plot_data.hpp"

namespace m2mlat::report {

std::string full_loop_table(std::span<const analysis::FullLoopResult> results);
// One object per file: scenario, file, format, events, and per quantity key its summary and the
// excluded events by reason.
nlohmann::json full_loop_json(std::span<const analysis::FullLoopResult> results);
// The thresholds of the first quantity of the first file (every summary has the same), or null.
const std::vector<stats::ThresholdShare>* full_loop_thresholds(
    std::span<const analysis::FullLoopResult> results);
// The boxes of the figure: M2M, G2G, E2E of each file in that order (BoxData::scenario = the
// quantity's label, BoxData::group = the file's scenario); quantities a file lacks are left out.
std::vector<BoxData> full_loop_boxes(std::span<const analysis::FullLoopResult> results);
// The rows of the tables (text and HTML): scenario, quantity, events, excluded (missing / impossible /
// overflow), then summary_cells (n, median, IQR, mean, sd, min, max, P95, shares above), in ms.
// What a reader should know about one result's figures, one sentence each: an M2M whose median is below
// kSmallM2M (a baseline with both gyroscopes on one body gives about 0, and negative samples from the
// onset detectors' spread; a teleoperated vehicle's M2M holds a network and an actuator).
inline constexpr double kSmallM2MMs = 50;
std::vector<std::string> full_loop_notes(const analysis::FullLoopResult& result);

std::vector<std::string> full_loop_header(std::span<const analysis::FullLoopResult> results);
std::vector<std::vector<std::string>> full_loop_rows(std::span<const analysis::FullLoopResult> results);

}  // namespace m2mlat::report
