// A plain-text table for the terminal: a header row, aligned columns (text left, numbers right).
#pragma once

#include <string>
#include <vector>

namespace m2mlat::report {

class Table {
 public:
  explicit Table(std::vector<std::string> header) : header_(std::move(header)) {}
  // cells.size() must equal the header's; control characters in a cell are escaped (core::printable).
  void add_row(std::vector<std::string> cells);
  std::string render() const;                    // ends with a newline

 private:
  std::vector<std::string> header_;
  std::vector<std::vector<std::string>> rows_;
};

// Fixed-point text of a value in ms ("874.512"), or "-" for NaN.
std::string ms_text(double ms, int decimals = 1);
// "12.3 %" of a fraction in [0, 1], or "-" for NaN.
std::string percent_text(double fraction, int decimals = 1);

}  // namespace m2mlat::report
