#include "analysis/least_squares.hpp"

#include <cmath>
#include <limits>

#include <fmt/format.h>
#include <unsupported/Eigen/NonLinearOptimization>

#include "analysis/student_t.hpp"
#include "core/error.hpp"

namespace pbx {

namespace {
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

double total_sum_of_squares(const Eigen::VectorXd& y) {
  if (y.size() == 0) return 0;
  return (y.array() - y.mean()).square().sum();
}

// Adapter to Eigen's MINPACK functor interface.
struct LmFunctor {
  const ResidualFunction& f;
  int m;
  int values() const { return m; }
  int operator()(const Eigen::VectorXd& p, Eigen::VectorXd& r) const {
    f(p, r, nullptr);
    return 0;
  }
  int df(const Eigen::VectorXd& p, Eigen::MatrixXd& J) const {
    Eigen::VectorXd r(m);
    f(p, r, &J);
    return 0;
  }
};
}  // namespace

const FitParameter& FitResult::operator[](const std::string& name) const {
  for (const auto& p : params) {
    if (p.name == name) return p;
  }
  throw std::out_of_range("no fitted parameter " + name);
}
FitParameter& FitResult::operator[](const std::string& name) {
  return const_cast<FitParameter&>(static_cast<const FitResult&>(*this)[name]);
}

Json FitResult::to_json() const {
  Json j = Json::object();
  j["model"] = model;
  j["method"] = method;
  Json ps = Json::object();
  for (const auto& p : params) {
    Json q = Json::object();
    q["value"] = p.value;
    q["unit"] = p.unit;
    q["std_error"] = p.std_error;
    q["ci_low"] = p.ci_low;
    q["ci_high"] = p.ci_high;
    ps[p.name] = q;
  }
  j["parameters"] = ps;
  j["confidence"] = confidence;
  j["n"] = n;
  j["dof"] = dof;
  j["sse"] = sse;
  j["rmse"] = rmse;
  j["r2"] = r2;
  j["converged"] = converged;
  if (!note.empty()) j["note"] = note;
  return j;
}

void set_confidence_intervals(FitResult& fit, const Eigen::MatrixXd& J) {
  const int p = static_cast<int>(fit.params.size());
  fit.dof = fit.n - p;
  double t = kNaN;
  Eigen::MatrixXd cov = Eigen::MatrixXd::Constant(p, p, kNaN);
  if (fit.dof <= 0) {
    // as many parameters as points: the curve passes through every point and says nothing about
    // its own uncertainty (the intervals stay NaN, and the fit says why)
    const std::string why = fmt::format(
        "no degrees of freedom ({} points for {} parameters): the fit passes through "
        "every point, so no confidence interval can be given",
        fit.n, p);
    fit.note = fit.note.empty() ? why : fit.note + "; " + why;
  }
  if (fit.dof > 0) {
    t = student_t_quantile(0.5 * (1.0 + fit.confidence), fit.dof);
    const double s2 = fit.sse / fit.dof;
    // Columns scaled to unit norm first: with sigma0 in Pa (~1e8) beside an alpha of ~0.3, J^T J
    // spans 15 decades and the LU's relative pivot threshold declared it singular (the full study's
    // Eq. 13 fit came out without intervals). The scaling leaves the covariance unchanged.
    Eigen::VectorXd scale(p);
    for (int k = 0; k < p; ++k) {
      const double norm = J.col(k).norm();
      scale(k) = norm > 0 ? 1.0 / norm : 0.0;
    }
    const Eigen::MatrixXd Js = J * scale.asDiagonal();
    Eigen::FullPivLU<Eigen::MatrixXd> lu(Js.transpose() * Js);
    if (lu.isInvertible() && (scale.array() > 0).all())
      cov = s2 * scale.asDiagonal() * lu.inverse() * scale.asDiagonal();
  }
  for (int k = 0; k < p; ++k) {
    auto& q = fit.params[std::size_t(k)];
    q.std_error = std::sqrt(cov(k, k));
    q.ci_low = q.value - t * q.std_error;
    q.ci_high = q.value + t * q.std_error;
  }
}

LineFit fit_line(const std::vector<double>& x, const std::vector<double>& y) {
  if (x.size() != y.size()) throw InputError("fit_line: x and y differ in length");
  LineFit f;
  f.n = static_cast<int>(x.size());
  if (f.n < 2) {
    f.slope = f.intercept = f.slope_se = f.intercept_se = f.r2 = f.rms_residual = kNaN;
    return f;
  }
  double mx = 0, my = 0;
  for (int i = 0; i < f.n; ++i) {
    mx += x[std::size_t(i)];
    my += y[std::size_t(i)];
  }
  mx /= f.n;
  my /= f.n;
  double sxx = 0, sxy = 0, syy = 0;
  for (int i = 0; i < f.n; ++i) {
    const double dx = x[std::size_t(i)] - mx, dy = y[std::size_t(i)] - my;
    sxx += dx * dx;
    sxy += dx * dy;
    syy += dy * dy;
  }
  if (sxx <= 0) {
    f.slope = f.intercept = f.slope_se = f.intercept_se = f.r2 = f.rms_residual = kNaN;
    return f;
  }
  f.slope = sxy / sxx;
  f.intercept = my - f.slope * mx;
  double sse = 0;
  for (int i = 0; i < f.n; ++i) {
    const double r = y[std::size_t(i)] - f.intercept - f.slope * x[std::size_t(i)];
    sse += r * r;
  }
  f.rms_residual = std::sqrt(sse / f.n);
  f.r2 = syy > 0 ? 1.0 - sse / syy : 1.0;
  if (f.n > 2) {
    const double s2 = sse / (f.n - 2);
    f.slope_se = std::sqrt(s2 / sxx);
    f.intercept_se = std::sqrt(s2 * (1.0 / f.n + mx * mx / sxx));
  } else {
    f.slope_se = f.intercept_se = kNaN;
  }
  return f;
}

FitResult linear_least_squares(const Eigen::MatrixXd& X, const Eigen::VectorXd& y,
                               const std::vector<std::string>& names, const std::vector<std::string>& units,
                               double confidence) {
  const auto p = X.cols();
  if (X.rows() != y.size() || std::size_t(p) != names.size() || names.size() != units.size()) {
    throw InputError("linear_least_squares: inconsistent sizes");
  }
  if (X.rows() < p) {
    throw InputError(fmt::format("linear least squares needs at least {} points, got {}", p, X.rows()));
  }
  if (!X.allFinite() || !y.allFinite())
    throw InputError("linear least squares: the data hold a value that is not a finite number (an overflow?)");
  FitResult fit;
  fit.method = "linear least squares (QR)";
  fit.confidence = confidence;
  fit.n = static_cast<int>(X.rows());
  Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(X);
  if (qr.rank() < p) throw InputError("linear least squares: the data do not determine all parameters");
  Eigen::VectorXd beta = qr.solve(y);
  const Eigen::VectorXd r = y - X * beta;
  fit.sse = r.squaredNorm();
  fit.rmse = std::sqrt(fit.sse / fit.n);
  const double sst = total_sum_of_squares(y);
  fit.r2 = sst > 0 ? 1.0 - fit.sse / sst : sst == 0 ? 1.0 : kNaN;
  for (Eigen::Index k = 0; k < p; ++k) {
    fit.params.push_back({names[std::size_t(k)], units[std::size_t(k)], beta(k), 0, 0, 0});
  }
  set_confidence_intervals(fit, X);
  fit.converged = beta.allFinite();
  return fit;
}

FitResult levenberg_marquardt(const ResidualFunction& residuals, int n, const Eigen::VectorXd& p0,
                              const Eigen::VectorXd& y_for_r2, const std::vector<std::string>& names,
                              const std::vector<std::string>& units, double confidence) {
  const auto p = p0.size();
  if (std::size_t(p) != names.size() || names.size() != units.size()) {
    throw InputError("levenberg_marquardt: inconsistent sizes");
  }
  if (n < p) throw InputError(fmt::format("nonlinear least squares needs at least {} points, got {}", p, n));
  {
    Eigen::VectorXd r0(n);
    residuals(p0, r0, nullptr);
    if (!r0.allFinite() || !y_for_r2.allFinite())
      throw InputError("nonlinear least squares: the data hold a value that is not a finite number (an overflow?)");
  }
  LmFunctor functor{residuals, n};
  Eigen::LevenbergMarquardt<LmFunctor> lm(functor);
  lm.parameters.ftol = 1e-14;
  lm.parameters.xtol = 1e-14;
  lm.parameters.maxfev = 2000;
  Eigen::VectorXd x = p0;
  const auto status = lm.minimize(x);
  FitResult fit;
  fit.method = "nonlinear least squares (Levenberg-Marquardt)";
  fit.confidence = confidence;
  fit.n = n;
  // Exact fits end on "relative reduction too small"-type codes; only these are failures.
  fit.converged = status != Eigen::LevenbergMarquardtSpace::ImproperInputParameters &&
                  status != Eigen::LevenbergMarquardtSpace::TooManyFunctionEvaluation && x.allFinite();
  if (!fit.converged) fit.note = fmt::format("Levenberg-Marquardt stopped with status {}", int(status));
  if (!x.allFinite()) fit.converged = false;
  Eigen::VectorXd r(n);
  Eigen::MatrixXd J(n, p);
  residuals(x, r, &J);
  fit.sse = r.squaredNorm();
  fit.rmse = std::sqrt(fit.sse / n);
  const double sst = total_sum_of_squares(y_for_r2);
  fit.r2 = sst > 0 ? 1.0 - fit.sse / sst : sst == 0 ? 1.0 : kNaN;
  for (Eigen::Index k = 0; k < p; ++k) {
    fit.params.push_back({names[std::size_t(k)], units[std::size_t(k)], x(k), 0, 0, 0});
  }
  set_confidence_intervals(fit, J);
  return fit;
}

}  // namespace pbx
