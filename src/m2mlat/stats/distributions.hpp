// Tail probabilities of the distributions the comparison tests need: normal, Student's t, F and
// beta. Thin wrappers over Boost.Math (header-only, Debian's libboost-math-dev), so that no special
// function is written by hand here; the wrappers only fix the argument conventions and turn Boost's
// domain errors into core::Error(internal) (a NaN or a negative degree of freedom is a bug upstream).
#pragma once

namespace m2mlat::stats {

double normal_cdf(double z);                           // P(Z <= z), Z standard normal
double normal_sf(double z);                            // P(Z > z), accurate far in the upper tail
double normal_quantile(double p);                      // z with P(Z <= z) = p, p in (0, 1)
double students_t_sf(double t, double df);             // P(T > t), df > 0
double fisher_f_sf(double f, double df1, double df2);  // P(F > f), f >= 0, df1, df2 > 0
double beta_cdf(double x, double a, double b);         // regularised incomplete beta I_x(a, b)

}  // namespace m2mlat::stats
