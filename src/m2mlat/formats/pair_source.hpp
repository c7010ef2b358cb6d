// Pairs-file rows taken from a source a block at a time. The pairs writers (pairs_export.hpp,
// rig_paired.hpp) ask a PairSource for a few thousand rows at once, so that a caller who holds its
// pairs in its own type (the matcher's: analysis/pairs_file.cpp) converts them one block at a time
// instead of building a second table of every row and per-pair columns beside its pairs (issue 19:
// at 10^7 events a side those tables were over 600 MB of `m2mlat pair -o`'s peak).
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <string_view>
#include <vector>

#include "m2mlat/formats/pair_row.hpp"

namespace m2mlat::formats {

// One row as the writers take it: the pair and what the file holds beside it.
struct PairRecord {
  PairRow row;
  std::int64_t session = 0;  // the store session of the cause event; 0 = unknown (written empty)
  // The uncertainty columns (pairs_export.hpp), ns; nullopt = unknown. Read only for the columns the
  // source has (PairSource::columns).
  std::optional<std::int64_t> max_error_ns, u_ns, U95_ns;
  // Whether the statistics hold the pair, and if not why (a short snake_case name): read only when the
  // source has the columns (PairColumns::statistics).
  bool in_statistics = true;
  std::string_view left_out;
  // The alignment model's posterior probability of the pair (`--matcher model`): read only when the
  // source has the column (PairColumns::probability); nullopt writes it empty.
  std::optional<float> probability;
};

// Which optional uncertainty columns a source's file has (on every row, empty where unknown).
struct PairColumns {
  bool max_error_ns = false;
  bool u_ns = false;
  bool U95_ns = false;
  bool statistics = false;  // in_statistics and left_out
  bool probability = false;
};

class PairSource {
 public:
  virtual ~PairSource() = default;
  virtual std::size_t size() const = 0;  // rows
  virtual PairColumns columns() const = 0;
  // Writes rows [first, first + out.size()) to `out`; first + out.size() <= size().
  virtual void fill(std::size_t first, std::span<PairRecord> out) const = 0;
};

// Rows per block: 4096 rows of 144 bytes, under half a MiB whatever the number of pairs.
inline constexpr std::size_t kPairBlockRows = 4096;

// A source's rows in order, read a block at a time into one buffer of at most kPairBlockRows rows:
// the one loop every writer reads its rows through.
class PairBlockReader {
 public:
  explicit PairBlockReader(const PairSource& source);
  // Row i (< size()); reads the block that starts at i when i is not in the current one.
  const PairRecord& at(std::size_t i) {
    if (i < first_ || i - first_ >= filled_) load(i);
    return block_[i - first_];
  }

 private:
  void load(std::size_t i);
  const PairSource& source_;
  std::vector<PairRecord> block_;
  std::size_t first_ = 0;   // the row of block_[0]
  std::size_t filled_ = 0;  // rows of block_ read
};

}  // namespace m2mlat::formats
