// A span of pairs-file rows as a pair source.
#include "m2mlat/formats/pair_rows_source.hpp"

#include <fmt/format.h>

#include <string_view>

#include "m2mlat/core/error.hpp"

namespace m2mlat::formats {

PairRowsSource::PairRowsSource(std::span<const PairRow> rows, const PairExportOptions& options)
    : rows_(rows),
      sessions_(options.sessions),
      max_error_ns_(options.max_error_ns),
      u_ns_(options.u_ns),
      U95_ns_(options.U95_ns),
      left_out_(options.left_out) {
  auto check_size = [&](std::size_t size, std::string_view what) {
    if (size != 0 && size != rows.size())
      throw core::Error(core::ErrorKind::internal,
                        fmt::format("pair export: {} {} for {} pairs", size, what, rows.size()));
  };
  check_size(max_error_ns_.size(), "max_error_ns");
  check_size(u_ns_.size(), "u_ns");
  check_size(U95_ns_.size(), "U95_ns");
  check_size(sessions_.size(), "sessions");
  check_size(left_out_.size(), "left_out");
}

PairColumns PairRowsSource::columns() const {
  return {!max_error_ns_.empty(), !u_ns_.empty(), !U95_ns_.empty(), !left_out_.empty()};
}

void PairRowsSource::fill(std::size_t first, std::span<PairRecord> out) const {
  // An empty column reads as unknown on every row.
  const auto value = [](std::span<const std::optional<std::int64_t>> column, std::size_t i) {
    return column.empty() ? std::nullopt : column[i];
  };
  for (std::size_t j = 0; j < out.size(); ++j) {
    const std::size_t i = first + j;
    out[j] = {rows_[i], sessions_.empty() ? 0 : sessions_[i], value(max_error_ns_, i), value(u_ns_, i),
              value(U95_ns_, i), left_out_.empty() || left_out_[i].empty(),
              left_out_.empty() ? std::string_view() : left_out_[i], std::nullopt};
  }
}

}  // namespace m2mlat::formats
