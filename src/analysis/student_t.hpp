#pragma once
// Student-t distribution, for confidence intervals of fitted constants. Evaluated by Boost.Math
// (boost/math/distributions/students_t.hpp): the field's well-tested implementation, not ours.
namespace pbx {

// P(T <= t) for Student's t with `dof` > 0 degrees of freedom.
double student_t_cdf(double t, double dof);

// Quantile t_p such that P(T <= t_p) = p, 0 < p < 1.
double student_t_quantile(double p, double dof);

}  // namespace pbx
