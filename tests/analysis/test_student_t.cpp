#include <cmath>
#include <numbers>

#include <gtest/gtest.h>

#include "analysis/student_t.hpp"

using namespace pbx;

// Closed forms: dof 1 (Cauchy) t = tan(pi (p - 1/2)); dof 2 t = (2p - 1)/sqrt(2 p (1 - p));
// dof 4 t = sign * sqrt(4 (cos(acos(sqrt(a))/3)/sqrt(a) - 1)), a = 4 p (1 - p).
TEST(StudentT, QuantileMatchesClosedFormsForOneTwoAndFourDegrees) {
  for (double p : {0.6, 0.9, 0.975, 0.995}) {
    EXPECT_NEAR(student_t_quantile(p, 1), std::tan(std::numbers::pi * (p - 0.5)),
                1e-9 * std::tan(std::numbers::pi * (p - 0.5)));
    EXPECT_NEAR(student_t_quantile(p, 2), (2 * p - 1) / std::sqrt(2 * p * (1 - p)), 1e-10);
    const double a = 4 * p * (1 - p);
    const double t4 = std::sqrt(4 * (std::cos(std::acos(std::sqrt(a)) / 3) / std::sqrt(a) - 1));
    EXPECT_NEAR(student_t_quantile(p, 4), t4, 1e-10);
  }
}

TEST(StudentT, QuantileMatchesPublishedTableAndNormalLimit) {
  // Two-sided 95 % values of standard t tables.
  EXPECT_NEAR(student_t_quantile(0.975, 10), 2.228139, 1e-6);
  EXPECT_NEAR(student_t_quantile(0.975, 30), 2.042272, 1e-6);
  EXPECT_NEAR(student_t_quantile(0.975, 1e7), 1.959964, 1e-5);  // the normal quantile
  EXPECT_NEAR(student_t_quantile(0.025, 10), -2.228139, 1e-6);
  EXPECT_NEAR(student_t_cdf(student_t_quantile(0.8, 3.5), 3.5), 0.8, 1e-12);
}
