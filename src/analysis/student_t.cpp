#include "analysis/student_t.hpp"

#include <cmath>

#include <boost/math/distributions/students_t.hpp>
#include <fmt/format.h>

#include "core/error.hpp"

namespace pbx {

namespace {
// Boost's default policy throws std::domain_error on bad arguments; the checks below come first so
// that a user sees which argument and value, as everywhere else.
void check_dof(const char* fn, double dof) {
  if (!(dof > 0) || std::isinf(dof))
    throw InputError(fmt::format("{}: degrees of freedom must be finite and > 0 (got {})", fn, dof));
}
}  // namespace

double student_t_cdf(double t, double dof) {
  check_dof("student_t_cdf", dof);
  if (std::isnan(t)) throw InputError("student_t_cdf: t is NaN");
  if (std::isinf(t)) return t > 0 ? 1.0 : 0.0;
  return boost::math::cdf(boost::math::students_t_distribution<double>(dof), t);
}

double student_t_quantile(double p, double dof) {
  if (!(p > 0 && p < 1)) throw InputError(fmt::format("student_t_quantile: p must be in (0, 1) (got {})", p));
  check_dof("student_t_quantile", dof);
  return boost::math::quantile(boost::math::students_t_distribution<double>(dof), p);
}

}  // namespace pbx
