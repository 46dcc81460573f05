#include "analysis/density_law.hpp"

#include <cmath>

#include <fmt/format.h>

#include "core/error.hpp"

namespace pbx {

double density_law(double density, double k, double n, double rho0, double modulus_upper) {
  return modulus_upper * k * std::pow(density / rho0, n);
}

double mixture_density(double porosity, double w_grain, double rho_grain, double rho_binder) {
  return (1.0 - porosity) / (w_grain / rho_grain + (1.0 - w_grain) / rho_binder);
}

FitResult fit_density_law(const std::vector<double>& rho, const std::vector<double>& M, double rho0, double MU,
                          double confidence) {
  if (rho.size() != M.size()) throw InputError("Eq. 19-22 fit: density and modulus columns differ in length");
  if (rho.size() < 2) throw InputError(fmt::format("Eq. 19-22 fit needs at least 2 densities, got {}", rho.size()));
  if (!(rho0 > 0) || !(MU > 0)) throw InputError("Eq. 19-22 fit: rho0 and the upper-bound modulus must be > 0");
  const auto n = static_cast<Eigen::Index>(rho.size());
  Eigen::MatrixXd X(n, 2);
  Eigen::VectorXd y(n);
  for (Eigen::Index i = 0; i < n; ++i) {
    const auto u = std::size_t(i);
    if (!(rho[u] > 0) || !(M[u] > 0)) {
      throw InputError(
          fmt::format("Eq. 19-22 fit: point {} has density {} and modulus {}; both must be > 0", i, rho[u], M[u]));
    }
    X(i, 0) = 1.0;
    X(i, 1) = std::log(rho[u] / rho0);
    y(i) = std::log(M[u] / MU);
  }
  FitResult fit = linear_least_squares(X, y, {"ln_k", "n"}, {"", ""}, confidence);
  fit.model = "eq18: M/M^U = k (rho/rho0)^n";
  fit.method = "linear least squares on ln(M/M^U) against ln(rho/rho0) (Eq. 19-20)";
  const FitParameter lk = fit["ln_k"];
  fit.params.front() = {
      "k", "", std::exp(lk.value), std::exp(lk.value) * lk.std_error, std::exp(lk.ci_low), std::exp(lk.ci_high)};
  fit.note = fit.note.empty() ? std::string("sse/rmse/r2 are of ln(M/M^U)")
                              : std::string("sse/rmse/r2 are of ln(M/M^U)") + "; " + fit.note;
  return fit;
}

}  // namespace pbx
