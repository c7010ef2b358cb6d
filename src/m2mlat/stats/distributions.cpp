// Boost.Math behind the small interface of distributions.hpp.
#include "m2mlat/stats/distributions.hpp"

#include <fmt/format.h>

#include <boost/math/distributions/beta.hpp>
#include <boost/math/distributions/fisher_f.hpp>
#include <boost/math/distributions/normal.hpp>
#include <boost/math/distributions/students_t.hpp>
#include <stdexcept>

#include "m2mlat/core/error.hpp"

namespace m2mlat::stats {

namespace {
template <class F>
double guarded(const char* what, F&& f) {
  try {
    return f();
  } catch (const std::exception& e) {
    throw core::Error(core::ErrorKind::internal, fmt::format("{}: {}", what, e.what()));
  }
}
}  // namespace

double normal_cdf(double z) {
  return guarded("normal_cdf", [&] { return boost::math::cdf(boost::math::normal_distribution<>(), z); });
}

double normal_sf(double z) {
  return guarded("normal_sf", [&] {
    return boost::math::cdf(boost::math::complement(boost::math::normal_distribution<>(), z));
  });
}

double normal_quantile(double p) {
  return guarded("normal_quantile",
                 [&] { return boost::math::quantile(boost::math::normal_distribution<>(), p); });
}

double students_t_sf(double t, double df) {
  return guarded("students_t_sf", [&] {
    return boost::math::cdf(boost::math::complement(boost::math::students_t_distribution<>(df), t));
  });
}

double fisher_f_sf(double f, double df1, double df2) {
  return guarded("fisher_f_sf", [&] {
    return boost::math::cdf(boost::math::complement(boost::math::fisher_f_distribution<>(df1, df2), f));
  });
}

double beta_cdf(double x, double a, double b) {
  return guarded("beta_cdf", [&] { return boost::math::cdf(boost::math::beta_distribution<>(a, b), x); });
}

}  // namespace m2mlat::stats
