// The BLOB layout of a block of raw rate samples (the rate_blocks table's `samples` column), version 1.
//
// Layout 1: `count` records of 18 bytes, back to back, all integers little-endian two's complement:
//   offset 0  int64 time_ns   the stamp, ns on the row's clock
//   offset 8  int32 bound_ns  the half-width of the stamp's interval, ns (>= 0)
//   offset 12 int16 x, y, z   the angular rate in the chip's counts (row's counts_per_deg_s)
// Stamps are in time order (each >= the one before). Fixed-size records keep a damaged BLOB
// detectable by its length alone and let a reader seek to sample k without decoding the rest. A new
// layout gets a new number in the row's `layout` column; readers refuse one they do not know.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "m2mlat/core/rate_sample.hpp"
#include "m2mlat/store/records.hpp"

namespace m2mlat::store::rate_block {

inline constexpr std::int64_t kLayout = 1;
inline constexpr std::size_t kSampleBytes = 18;
// Samples per block at most: 0.5 s at 8 kHz, a 72 KiB BLOB (kept in step with schema.cpp's CHECK).
inline constexpr std::size_t kMaxSamples = 4096;

std::vector<std::uint8_t> encode(std::span<const core::RateSample> samples);

// Decodes a BLOB of layout `layout` that should hold `count` samples. Throws core::Error(data)
// "<where>: ..." (where names the store, table and row) for an unknown layout, a length that is not
// count * 18 bytes, a negative bound or a stamp earlier than the one before it.
std::vector<core::RateSample> decode(std::span<const std::uint8_t> bytes, std::int64_t layout,
                                     std::int64_t count, const std::string& where);

// `samples` (in time order) as blocks of at most kMaxSamples for one session and channel, sample k
// numbered first_index + k.
std::vector<RateBlock> split(std::int64_t session_id, const std::string& channel, core::Clock clock,
                             double counts_per_deg_s, std::span<const core::RateSample> samples,
                             std::uint64_t first_index = 0);

}  // namespace m2mlat::store::rate_block
