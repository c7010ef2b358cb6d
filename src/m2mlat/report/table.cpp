// Column widths from the longest cell; numbers (cells starting with a digit, sign or '-') right-aligned.
#include "m2mlat/report/table.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "m2mlat/core/error.hpp"
#include "m2mlat/core/printable.hpp"

namespace m2mlat::report {

namespace {
bool numeric(const std::string& cell) {
  return !cell.empty() &&
         (std::isdigit(static_cast<unsigned char>(cell[0])) || cell[0] == '-' || cell[0] == '+');
}
// Display width: counts UTF-8 code points, not bytes, so "±" and "µ" align.
std::size_t width(const std::string& s) {
  return static_cast<std::size_t>(
      std::count_if(s.begin(), s.end(), [](char c) { return (c & 0xC0) != 0x80; }));
}
}  // namespace

void Table::add_row(std::vector<std::string> cells) {
  if (cells.size() != header_.size())
    throw core::Error(core::ErrorKind::internal, "table row of the wrong width");
  // Cells hold names from input: control characters would drive the terminal (core/printable.hpp).
  for (auto& cell : cells) cell = core::printable(cell);
  rows_.push_back(std::move(cells));
}

std::string Table::render() const {
  std::vector<std::size_t> widths(header_.size());
  for (std::size_t c = 0; c < header_.size(); ++c) {
    widths[c] = width(header_[c]);
    for (const auto& row : rows_) widths[c] = std::max(widths[c], width(row[c]));
  }
  std::string out;
  auto line = [&](const std::vector<std::string>& cells, bool header) {
    for (std::size_t c = 0; c < cells.size(); ++c) {
      const std::size_t pad = widths[c] - width(cells[c]);
      const bool right = !header && c > 0 && numeric(cells[c]);
      if (c > 0) out += "  ";
      if (right) out.append(pad, ' ');
      out += cells[c];
      if (!right && c + 1 < cells.size()) out.append(pad, ' ');
    }
    out += '\n';
  };
  line(header_, true);
  std::size_t total = 0;
  for (auto w : widths) total += w;
  out.append(total + 2 * (widths.empty() ? 0 : widths.size() - 1), '-');
  out += '\n';
  for (const auto& row : rows_) line(row, false);
  return out;
}

std::string ms_text(double ms, int decimals) {
  return std::isnan(ms) ? "-" : fmt::format("{:.{}f}", ms, decimals);
}

std::string percent_text(double fraction, int decimals) {
  return std::isnan(fraction) ? "-" : fmt::format("{:.{}f} %", 100.0 * fraction, decimals);
}

}  // namespace m2mlat::report
