// A table of pairs-file rows held whole (a span of PairRow and the export options' per-pair columns)
// as a PairSource: what the writers' span entry points (write_pairs_csv, write_pairs_jsonl,
// write_rig_paired_csv, export_pairs) hand to their block-by-block loop.
#pragma once

#include <span>
#include <string_view>

#include "m2mlat/formats/pair_row.hpp"
#include "m2mlat/formats/pair_source.hpp"
#include "m2mlat/formats/pairs_export.hpp"

namespace m2mlat::formats {

class PairRowsSource final : public PairSource {
 public:
  // Keeps views of `rows` and of options' sessions, max_error_ns, u_ns, U95_ns and left_out (which must outlive
  // it). Throws core::Error(internal) if a non-empty one of those does not have one entry per row.
  explicit PairRowsSource(std::span<const PairRow> rows, const PairExportOptions& options = {});

  std::size_t size() const override { return rows_.size(); }
  PairColumns columns() const override;
  void fill(std::size_t first, std::span<PairRecord> out) const override;

 private:
  std::span<const PairRow> rows_;
  std::span<const std::int64_t> sessions_;
  std::span<const std::optional<std::int64_t>> max_error_ns_, u_ns_, U95_ns_;
  std::span<const std::string_view> left_out_;
};

}  // namespace m2mlat::formats
