#include <cmath>

#include <gtest/gtest.h>

#include "analysis/least_squares.hpp"
#include "analysis/student_t.hpp"

using namespace pbx;

TEST(LeastSquares, LineFitStandardErrorsMatchTextbookFormulas) {
  // y = 1 + 2x with residuals +-0.1 alternating: SSE = 5 * 0.01.
  std::vector<double> x{0, 1, 2, 3, 4}, y;
  for (double xi : x) y.push_back(1 + 2 * xi + (int(xi) % 2 ? 0.1 : -0.1));
  const LineFit f = fit_line(x, y);
  // For these points Sxx = 10 (mean x = 2), so SE(slope) = sqrt(s^2 / 10), s^2 = SSE / 3.
  Eigen::MatrixXd X(5, 2);
  Eigen::VectorXd Y(5);
  for (int i = 0; i < 5; ++i) {
    X(i, 0) = 1;
    X(i, 1) = x[i];
    Y(i) = y[i];
  }
  const FitResult g = linear_least_squares(X, Y, {"a", "b"}, {"", ""});
  EXPECT_NEAR(f.slope, g["b"].value, 1e-14);
  EXPECT_NEAR(f.intercept, g["a"].value, 1e-14);
  const double s2 = g.sse / 3.0;
  EXPECT_NEAR(f.slope_se, std::sqrt(s2 / 10.0), 1e-14);
  EXPECT_NEAR(g["b"].std_error, std::sqrt(s2 / 10.0), 1e-14);
  EXPECT_NEAR(g["b"].ci_high - g["b"].value, student_t_quantile(0.975, 3) * std::sqrt(s2 / 10.0), 1e-13);
}

TEST(LeastSquares, LevenbergMarquardtRecoversExponentialDecayAndItsLinearisedCovariance) {
  // y = 3 exp(-0.7 x) exactly: LM must land on the constants; CI half-widths are 0 (SSE = 0).
  const int n = 12;
  std::vector<double> x(n), y(n);
  Eigen::VectorXd Y(n);
  for (int i = 0; i < n; ++i) {
    x[i] = 0.25 * i;
    y[i] = 3 * std::exp(-0.7 * x[i]);
    Y(i) = y[i];
  }
  auto res = [&](const Eigen::VectorXd& p, Eigen::VectorXd& r, Eigen::MatrixXd* J) {
    for (int i = 0; i < n; ++i) {
      const double e = std::exp(-p(1) * x[i]);
      r(i) = p(0) * e - y[i];
      if (J) {
        (*J)(i, 0) = e;
        (*J)(i, 1) = -p(0) * x[i] * e;
      }
    }
  };
  Eigen::VectorXd p0(2);
  p0 << 1.0, 0.2;
  const FitResult f = levenberg_marquardt(res, n, p0, Y, {"a", "k"}, {"", ""});
  EXPECT_TRUE(f.converged) << f.note;
  EXPECT_NEAR(f["a"].value, 3.0, 1e-10);
  EXPECT_NEAR(f["k"].value, 0.7, 1e-10);
  EXPECT_EQ(f.dof, n - 2);
  EXPECT_LT(f["k"].ci_high - f["k"].ci_low, 1e-8);
}
