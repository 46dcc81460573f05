#include "analysis/temperature_law.hpp"

#include <cmath>

#include <fmt/format.h>

#include "core/error.hpp"

namespace pbx {

namespace {
void check(const std::vector<double>& T, const std::vector<double>& s, double T0) {
  if (T.size() != s.size()) throw InputError("Eq. 13 fit: temperature and strength columns differ in length");
  if (T.size() < 2) throw InputError(fmt::format("Eq. 13 fit needs at least 2 temperatures, got {}", T.size()));
  if (!(T0 > 0)) throw InputError(fmt::format("Eq. 13 fit: reference temperature T0 must be > 0 K (got {})", T0));
  for (std::size_t i = 0; i < T.size(); ++i) {
    if (!(T[i] > 0) || !(s[i] > 0)) {
      throw InputError(
          fmt::format("Eq. 13 fit: point {} has T = {} K, strength = {} Pa; both must be > 0", i, T[i], s[i]));
    }
  }
}
const char* kModel = "eq13: sigma_c = sigma0 exp(alpha (1 - T/T0))";
}  // namespace

double temperature_law(double T_K, double sigma0, double alpha, double T0_K) {
  return sigma0 * std::exp(alpha * (1.0 - T_K / T0_K));
}

FitResult fit_temperature_law_loglinear(const std::vector<double>& T_K, const std::vector<double>& strength_Pa,
                                        double T0_K, double confidence) {
  check(T_K, strength_Pa, T0_K);
  const auto n = static_cast<Eigen::Index>(T_K.size());
  Eigen::MatrixXd X(n, 2);
  Eigen::VectorXd y(n);
  for (Eigen::Index i = 0; i < n; ++i) {
    X(i, 0) = 1.0;
    X(i, 1) = 1.0 - T_K[std::size_t(i)] / T0_K;
    y(i) = std::log(strength_Pa[std::size_t(i)]);
  }
  FitResult fit = linear_least_squares(X, y, {"ln_sigma0", "alpha"}, {"", ""}, confidence);
  fit.model = kModel;
  fit.method = "linear least squares on ln sigma_c (log-linear)";
  FitParameter& lns = fit["ln_sigma0"];
  FitParameter s0{"sigma0",
                  "Pa",
                  std::exp(lns.value),
                  std::exp(lns.value) * lns.std_error,
                  std::exp(lns.ci_low),
                  std::exp(lns.ci_high)};
  fit.params.insert(fit.params.begin(), s0);
  fit.params.erase(fit.params.begin() + 1);
  // The quality figures of a log fit are in ln units; restate SSE in Pa^2 so the two methods compare.
  double sse = 0;
  for (std::size_t i = 0; i < T_K.size(); ++i) {
    const double r = temperature_law(T_K[i], s0.value, fit["alpha"].value, T0_K) - strength_Pa[i];
    sse += r * r;
  }
  fit.note = fit.note.empty()
                 ? std::string(fmt::format("sse/rmse/r2 are of ln(sigma_c); SSE on sigma_c = {:.6g} Pa^2", sse))
                 : std::string(fmt::format("sse/rmse/r2 are of ln(sigma_c); SSE on sigma_c = {:.6g} Pa^2", sse)) +
                       "; " + fit.note;
  return fit;
}

FitResult fit_temperature_law_nonlinear(const std::vector<double>& T_K, const std::vector<double>& strength_Pa,
                                        double T0_K, double confidence) {
  const FitResult start = fit_temperature_law_loglinear(T_K, strength_Pa, T0_K, confidence);
  const int n = static_cast<int>(T_K.size());
  Eigen::VectorXd y(n);
  for (int i = 0; i < n; ++i) y(i) = strength_Pa[std::size_t(i)];
  auto res = [&](const Eigen::VectorXd& p, Eigen::VectorXd& r, Eigen::MatrixXd* J) {
    for (int i = 0; i < n; ++i) {
      const double u = 1.0 - T_K[std::size_t(i)] / T0_K;
      const double e = std::exp(p(1) * u);
      r(i) = p(0) * e - y(i);
      if (J) {
        (*J)(i, 0) = e;
        (*J)(i, 1) = p(0) * e * u;
      }
    }
  };
  Eigen::VectorXd p0(2);
  p0 << start["sigma0"].value, start["alpha"].value;
  FitResult fit = levenberg_marquardt(res, n, p0, y, {"sigma0", "alpha"}, {"Pa", ""}, confidence);
  fit.model = kModel;
  fit.method = "nonlinear least squares (Levenberg-Marquardt) on sigma_c";
  return fit;
}

}  // namespace pbx
