#pragma once
// Student-t distribution, for confidence intervals of fitted constants.
namespace pbx {

// Regularised incomplete beta function I_x(a, b), by the continued fraction of DLMF 8.17.22
// evaluated with the modified Lentz method (with the symmetry I_x(a,b) = 1 - I_{1-x}(b,a) where
// the fraction converges slowly).
double incomplete_beta(double a, double b, double x);

// P(T <= t) for Student's t with `dof` > 0 degrees of freedom: 1 - I_{dof/(dof+t^2)}(dof/2, 1/2)/2.
double student_t_cdf(double t, double dof);

// Quantile t_p such that P(T <= t_p) = p, 0 < p < 1, found by bisection on student_t_cdf to
// 1e-13 relative (closed forms exist only for dof = 1, 2, 4; the tests use them as checks).
double student_t_quantile(double p, double dof);

}  // namespace pbx
