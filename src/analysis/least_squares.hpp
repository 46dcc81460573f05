#pragma once
// Least-squares fits with confidence intervals: ordinary linear least squares (QR) and
// nonlinear least squares (Eigen's Levenberg-Marquardt, MINPACK lmder). Intervals are
// value +- t_{(1+c)/2, n-p} * SE with SE^2 the diagonal of s^2 (J^T J)^-1, s^2 = SSE/(n-p)
// (J = design matrix or Jacobian at the optimum); they are NaN when n = p.
#include <functional>
#include <string>
#include <vector>

#include <Eigen/Dense>

#include "io/json.hpp"

namespace pbx {

struct FitParameter {
  std::string name;
  std::string unit;  // "" for dimensionless
  double value = 0;
  double std_error = 0;
  double ci_low = 0, ci_high = 0;
};

struct FitResult {
  std::string model;   // e.g. "eq13: sigma_c = sigma0 exp(alpha (1 - T/T0))"
  std::string method;  // e.g. "nonlinear least squares (Levenberg-Marquardt) on sigma_c"
  std::vector<FitParameter> params;
  int n = 0;    // data points
  int dof = 0;  // n - parameters
  double confidence = 0.95;
  double sse = 0;   // sum of squared residuals, in the fitted quantity's units
  double rmse = 0;  // sqrt(sse / n)
  double r2 = 0;    // 1 - sse / sum (y - mean y)^2
  bool converged = true;
  std::string note;

  const FitParameter& operator[](const std::string& name) const;
  FitParameter& operator[](const std::string& name);
  Json to_json() const;
};

// Straight line y = intercept + slope x.
struct LineFit {
  double slope = 0, intercept = 0;
  double slope_se = 0, intercept_se = 0;
  double r2 = 0;
  double rms_residual = 0;
  int n = 0;
};
LineFit fit_line(const std::vector<double>& x, const std::vector<double>& y);

// y ~ X beta. `names`/`units` label the columns of X.
FitResult linear_least_squares(const Eigen::MatrixXd& X, const Eigen::VectorXd& y,
                               const std::vector<std::string>& names, const std::vector<std::string>& units,
                               double confidence = 0.95);

// Residuals r(p) (size n) and, when J is not null, their Jacobian dr/dp (n x p).
using ResidualFunction = std::function<void(const Eigen::VectorXd& p, Eigen::VectorXd& r, Eigen::MatrixXd* J)>;

// Minimises |r(p)|^2 from p0 with tolerances 1e-14 (relative in p and SSE).
FitResult levenberg_marquardt(const ResidualFunction& residuals, int n, const Eigen::VectorXd& p0,
                              const Eigen::VectorXd& y_for_r2, const std::vector<std::string>& names,
                              const std::vector<std::string>& units, double confidence = 0.95);

// Fills std_error and the intervals of `fit` from the Jacobian J at the optimum.
void set_confidence_intervals(FitResult& fit, const Eigen::MatrixXd& J);

}  // namespace pbx
