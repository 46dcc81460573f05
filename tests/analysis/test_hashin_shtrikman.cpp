#include <cmath>

#include <gtest/gtest.h>

#include "analysis/hashin_shtrikman.hpp"

using namespace pbx;

// Classic two-phase Hashin-Shtrikman (1963) bounds for well-ordered phases (K1 > K2, G1 > G2):
// K+ = K1 + f2 / (1/(K2 - K1) + 3 f1/(3K1 + 4G1)),
// G+ = G1 + f2 / (1/(G2 - G1) + 6 f1 (K1 + 2G1)/(5 G1 (3K1 + 4G1))), and the same with 1 <-> 2 for the lower.
TEST(HashinShtrikman, TwoPhaseBoundsMatchTheClassicFormulas) {
  const double K1 = 10.59e9, G1 = 11.5e9, K2 = 0.33e9, G2 = 0.07e9, f2 = 0.048, f1 = 1 - f2;
  const auto b = hashin_shtrikman_bounds({{K1, G1, f1, "1"}, {K2, G2, f2, "2"}});
  const double Kp = K1 + f2 / (1 / (K2 - K1) + 3 * f1 / (3 * K1 + 4 * G1));
  const double Gp = G1 + f2 / (1 / (G2 - G1) + 6 * f1 * (K1 + 2 * G1) / (5 * G1 * (3 * K1 + 4 * G1)));
  const double Km = K2 + f1 / (1 / (K1 - K2) + 3 * f2 / (3 * K2 + 4 * G2));
  const double Gm = G2 + f1 / (1 / (G1 - G2) + 6 * f2 * (K2 + 2 * G2) / (5 * G2 * (3 * K2 + 4 * G2)));
  EXPECT_NEAR(b.K_upper / Kp, 1.0, 1e-12);
  EXPECT_NEAR(b.G_upper / Gp, 1.0, 1e-12);
  EXPECT_NEAR(b.K_lower / Km, 1.0, 1e-12);
  EXPECT_NEAR(b.G_lower / Gm, 1.0, 1e-12);
  // Bounds lie between Reuss and Voigt.
  EXPECT_LT(b.K_upper, f1 * K1 + f2 * K2);
  EXPECT_GT(b.K_lower, 1 / (f1 / K1 + f2 / K2));
}

TEST(HashinShtrikman, OnePhaseAndPores) {
  const auto one = hashin_shtrikman_bounds({{5e9, 3e9, 1.0, "solid"}});
  EXPECT_NEAR(one.K_upper, 5e9, 1e-3);
  EXPECT_NEAR(one.G_lower, 3e9, 1e-3);
  const auto porous = hashin_shtrikman_bounds({{5e9, 3e9, 0.9, "solid"}, {0, 0, 0.1, "pores"}});
  EXPECT_EQ(porous.K_lower, 0.0);
  EXPECT_EQ(porous.G_lower, 0.0);
  EXPECT_LT(porous.K_upper, 5e9);
  EXPECT_THROW(hashin_shtrikman_bounds({{5e9, 3e9, 0.5, "solid"}}), std::exception);
}
