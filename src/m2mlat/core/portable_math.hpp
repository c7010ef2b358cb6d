// Logarithm, exponential and cosine computed with + - * / only, so that they give the same bits on every
// platform. The C library's log and exp are not required to be correctly rounded and differ in the
// last place between glibc, musl, libc++ platforms and CPU generations; a one-ulp difference can
// move a simulated timestamp by a nanosecond, or a bootstrap resample's order statistic by a rank, and
// break the reproducibility of the simulator or of the confidence intervals.
// Accuracy: a few ulp, far more than either needs.
#pragma once

namespace m2mlat::core {

// Natural logarithm of a finite x > 0 (x <= 0 returns -infinity).
double portable_log(double x);
// e^x for finite x; underflows to 0 below about -745 and overflows to infinity above about 709.
double portable_exp(double x);
// cos x for finite x (reduced to [-pi, pi] with a split 2 pi: accurate for |x| up to about 1e6).
double portable_cos(double x);

}  // namespace m2mlat::core
