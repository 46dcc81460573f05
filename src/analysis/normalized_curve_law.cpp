#include "analysis/normalized_curve_law.hpp"

#include <cmath>
#include <limits>

#include <fmt/format.h>

#include "analysis/temperature_law.hpp"
#include "core/error.hpp"

namespace pbx {

double normalized_curve(double strain_percent, double A, double B, double n) {
  return A * strain_percent + B * std::pow(strain_percent, n);
}

double constitutive_stress(double strain, double T_K, double sigma0_Pa, double alpha, double T0_K, double A, double B,
                           double n) {
  return temperature_law(T_K, sigma0_Pa, alpha, T0_K) * normalized_curve(100.0 * strain, A, B, n);
}

FitResult fit_normalized_curve(const std::vector<double>& e, const std::vector<double>& s, double confidence) {
  if (e.size() != s.size()) throw InputError("Eq. 14 fit: strain and stress columns differ in length");
  if (e.size() < 3) throw InputError(fmt::format("Eq. 14 fit needs at least 3 points, got {}", e.size()));
  for (std::size_t i = 0; i < e.size(); ++i) {
    if (!(e[i] > 0) || !std::isfinite(s[i])) {
      throw InputError(
          fmt::format("Eq. 14 fit: point {} has strain {} %, sigma_n {}; strain must be > 0", i, e[i], s[i]));
    }
  }
  const int m = static_cast<int>(e.size());
  Eigen::VectorXd y(m);
  for (int i = 0; i < m; ++i) y(i) = s[std::size_t(i)];

  double best_sse = std::numeric_limits<double>::infinity();
  Eigen::VectorXd p0(3);
  p0 << 0.0, 1.0, 0.5;
  for (int k = 1; k <= 150; ++k) {
    const double n = 0.01 * k;
    Eigen::MatrixXd X(m, 2);
    for (int i = 0; i < m; ++i) {
      X(i, 0) = e[std::size_t(i)];
      X(i, 1) = std::pow(e[std::size_t(i)], n);
    }
    Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(X);
    if (qr.rank() < 2) continue;
    Eigen::VectorXd ab = qr.solve(y);
    const double sse = (X * ab - y).squaredNorm();
    if (sse < best_sse) {
      best_sse = sse;
      p0 << ab(0), ab(1), n;
    }
  }
  auto res = [&](const Eigen::VectorXd& p, Eigen::VectorXd& r, Eigen::MatrixXd* J) {
    for (int i = 0; i < m; ++i) {
      const double x = e[std::size_t(i)];
      const double xn = std::pow(x, p(2));
      r(i) = p(0) * x + p(1) * xn - y(i);
      if (J) {
        (*J)(i, 0) = x;
        (*J)(i, 1) = xn;
        (*J)(i, 2) = p(1) * xn * std::log(x);
      }
    }
  };
  FitResult fit = levenberg_marquardt(res, m, p0, y, {"A", "B", "n"}, {"", "", ""}, confidence);
  fit.model = "eq14: sigma_n = A e + B e^n, e = strain in percent";
  fit.method = "nonlinear least squares (Levenberg-Marquardt) on sigma_n";
  return fit;
}

}  // namespace pbx
