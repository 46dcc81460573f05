// The deformation-gradient update (solver/kinematics.hpp) against the exact F of a body stretched
// and then rotated: with constant L over each stage, F = exp(L2 t2) exp(L1 t1) = R U. The update
// (I + dt L) F is first-order accurate, so with 20,000 steps per stage it lands within 1e-4 of R U;
// the increment applied on the wrong side gives U R, 0.08 away (the mutation check's survivor of
// 2026-12-05, which the engine tests missed: J = det F does not see the order).
#include <cmath>

#include <gtest/gtest.h>

#include "solver/kinematics.hpp"

using namespace pbx;

TEST(Kinematics, StretchThenRotateGivesRU) {
  const double a = 0.2, w = M_PI / 6.0;  // ln of the stretch in x, rotation angle (30 degrees)
  const int n = 20000;
  Mat<2> L1 = Mat<2>::Zero(), L2 = Mat<2>::Zero();
  L1(0, 0) = a;  // over unit time: stretch exp(a) along x
  L2(0, 1) = -w, L2(1, 0) = w;
  Mat<2> F = Mat<2>::Identity();
  for (int k = 0; k < n; ++k) F = advance_deformation_gradient<2>(F, L1, 1.0 / n);
  for (int k = 0; k < n; ++k) F = advance_deformation_gradient<2>(F, L2, 1.0 / n);
  Mat<2> U = Mat<2>::Identity(), R;
  U(0, 0) = std::exp(a);
  R << std::cos(w), -std::sin(w), std::sin(w), std::cos(w);
  const Mat<2> RU = R * U, UR = U * R;
  EXPECT_LT((F - RU).norm(), 1e-4) << F;
  EXPECT_GT((RU - UR).norm(), 0.05);  // the two orders are told apart by far more than the tolerance
  // the rotation stage's forward-Euler growth, (1 + (w/n)^2)^(n/2) - 1 = 7e-6, sits within J's tolerance
  EXPECT_NEAR(F.determinant(), std::exp(a), 1e-4);
}
