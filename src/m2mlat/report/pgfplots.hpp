// Paper-ready figures: one pgfplots .tex file per plot plus its data files (whitespace-separated
// columns with a header), so a figure like the reference study's box plot can be dropped into a
// LaTeX paper with \input. Also figures.tex, a complete document that inputs them all (for a quick
// look, and for the test that compiles them with pdflatex).
//
// The figures read their data as \mtwomlatdir<file>.dat; \mtwomlatdir is empty unless the paper
// defines it first (\newcommand\mtwomlatdir{figures/}). Needs \usepackage{pgfplots} and
// \usepgfplotslibrary{statistics} (box plots); written for pgfplots compat 1.16 or later.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "m2mlat/report/report_model.hpp"

namespace m2mlat::report {

// Writes the files into `directory` (created if missing) and returns their names, figures first.
// Throws core::Error(io) naming a file that cannot be written.
std::vector<std::string> write_pgfplots(const Report& report, const std::filesystem::path& directory);

// TeX-escapes a label (_ % & # $ { } ~ ^ \).
std::string tex_escape(const std::string& text);

}  // namespace m2mlat::report
