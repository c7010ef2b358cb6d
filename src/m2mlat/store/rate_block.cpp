// Encoding and decoding of layout 1 (see rate_block.hpp), byte by byte so that the file reads the
// same on any host byte order.
#include "m2mlat/store/rate_block.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <type_traits>

#include "m2mlat/core/error.hpp"

namespace m2mlat::store::rate_block {

namespace {

template <typename T>
void put(std::vector<std::uint8_t>& out, T value) {
  const auto bits = static_cast<std::make_unsigned_t<T>>(value);
  for (std::size_t i = 0; i < sizeof(T); ++i) out.push_back(static_cast<std::uint8_t>(bits >> (8 * i)));
}

template <typename T>
T get(std::span<const std::uint8_t> bytes, std::size_t offset) {
  std::make_unsigned_t<T> bits = 0;
  for (std::size_t i = 0; i < sizeof(T); ++i)
    bits = static_cast<std::make_unsigned_t<T>>(
        bits | (static_cast<std::make_unsigned_t<T>>(bytes[offset + i]) << (8 * i)));
  return static_cast<T>(bits);
}

}  // namespace

std::vector<std::uint8_t> encode(std::span<const core::RateSample> samples) {
  std::vector<std::uint8_t> out;
  out.reserve(samples.size() * kSampleBytes);
  for (const core::RateSample& s : samples) {
    put(out, s.time_ns);
    put(out, s.bound_ns);
    for (const std::int16_t axis : s.raw) put(out, axis);
  }
  return out;
}

std::vector<core::RateSample> decode(std::span<const std::uint8_t> bytes, std::int64_t layout,
                                     std::int64_t count, const std::string& where) {
  if (layout != kLayout)
    core::throw_data_error(
        {where, 0}, fmt::format("field 'layout' is {} (this m2mlat reads layout {})", layout, kLayout));
  if (count < 1 || static_cast<std::size_t>(count) > kMaxSamples ||
      bytes.size() != static_cast<std::size_t>(count) * kSampleBytes)
    core::throw_data_error({where, 0},
                           fmt::format("field 'samples' holds {} bytes, but field 'count' {} needs {} "
                                       "({} bytes a sample, 1 to {} samples)",
                                       bytes.size(), count, count * static_cast<std::int64_t>(kSampleBytes),
                                       kSampleBytes, kMaxSamples));
  std::vector<core::RateSample> out(static_cast<std::size_t>(count));
  for (std::size_t k = 0; k < out.size(); ++k) {
    const std::size_t at = k * kSampleBytes;
    core::RateSample& s = out[k];
    s.time_ns = get<std::int64_t>(bytes, at);
    s.bound_ns = get<std::int32_t>(bytes, at + 8);
    for (std::size_t axis = 0; axis < 3; ++axis) s.raw[axis] = get<std::int16_t>(bytes, at + 12 + 2 * axis);
    if (s.bound_ns < 0)
      core::throw_data_error(
          {where, 0},
          fmt::format("field 'samples': sample {} has bound {} ns (expected >= 0)", k, s.bound_ns));
    if (k > 0 && s.time_ns < out[k - 1].time_ns)
      core::throw_data_error(
          {where, 0}, fmt::format("field 'samples': sample {} at {} ns is earlier than sample {} at {} ns", k,
                                  s.time_ns, k - 1, out[k - 1].time_ns));
  }
  return out;
}

std::vector<RateBlock> split(std::int64_t session_id, const std::string& channel, core::Clock clock,
                             double counts_per_deg_s, std::span<const core::RateSample> samples,
                             std::uint64_t first_index) {
  std::vector<RateBlock> out;
  for (std::size_t at = 0; at < samples.size(); at += kMaxSamples) {
    const auto part = samples.subspan(at, std::min(kMaxSamples, samples.size() - at));
    RateBlock block;
    block.session_id = session_id;
    block.channel = channel;
    block.clock = clock;
    block.counts_per_deg_s = counts_per_deg_s;
    block.first_index = first_index + at;
    block.samples.assign(part.begin(), part.end());
    out.push_back(std::move(block));
  }
  return out;
}

}  // namespace m2mlat::store::rate_block
