// How far a series' dependence reaches, and the block length a block bootstrap needs for it.
//
// Method (docs/statistics.md, "What is resampled"): the automatic block length of Politis and White
// (2004), with the correction of Patton, Politis and White (2009), for the circular block bootstrap.
// The autocorrelations are screened first: the smallest lag m after which K_N = max(5,
// ceil(sqrt(log10 N))) lags in a row lie inside +-2 sqrt(log10 N / N); if m = 0 the series is taken
// as independent (block length 1). Otherwise a flat-top lag window of width 2m estimates the
// spectral terms G and D, and the block length is (2 G^2 / D)^(1/3) N^(1/3), at most
// min(3 sqrt(N), N / 3).
#pragma once

#include <cstddef>
#include <span>
#include <vector>

namespace m2mlat::stats {

struct BlockLength {
  std::size_t length = 1;  // values a block; 1: independent
  std::size_t reach = 0;   // m above: the last lag still correlated (0: none)
  double lag1 = 0.0;       // the lag-1 autocorrelation (0 for a short or constant series)
  std::size_t used = 0;    // values the estimate used (all, or the stretches of a long series)
};

// The stretches [begin, end) of a series of `total` values its dependence is estimated from: the whole
// series up to 2^18 values, else 16 evenly spaced stretches of 2^14 consecutive values, so that the
// cost stays bounded (the autocorrelations are computed only as far as the screen needs: about 5 N
// operations for an independent series, at most 2^18 (sqrt(2^18) + 10)).
struct Stretch {
  std::size_t begin = 0, end = 0;
};
std::vector<Stretch> estimation_stretches(std::size_t total);

// The block length for a series of `total` values in time order, given by its estimation_stretches'
// values (one vector each, in order). A constant or short series (fewer than 8 values) is independent.
BlockLength block_length(std::span<const std::vector<double>> stretches, std::size_t total);
// The same for a whole series at hand.
BlockLength block_length(std::span<const double> series);

}  // namespace m2mlat::stats
