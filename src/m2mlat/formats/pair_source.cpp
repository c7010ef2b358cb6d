// Reading a pair source block by block.
#include "m2mlat/formats/pair_source.hpp"

#include <algorithm>

namespace m2mlat::formats {

PairBlockReader::PairBlockReader(const PairSource& source)
    : source_(source), block_(std::min(kPairBlockRows, source.size())) {}

void PairBlockReader::load(std::size_t i) {
  first_ = i;
  filled_ = std::min(block_.size(), source_.size() - i);
  source_.fill(first_, std::span<PairRecord>(block_).first(filled_));
}

}  // namespace m2mlat::formats
