#include <cmath>

#include <gtest/gtest.h>

#include "analysis/normalized_curve_law.hpp"

using namespace pbx;

TEST(NormalizedCurveLaw, PaperConstantsGiveTheTabulatedValuesInPercent) {
  // physics.md section 6: 0.853 / 0.963 / 1.045 / 1.060 / 1.009 at 0.5 / 1 / 2 / 3 / 5 %.
  const double A = -0.1206, B = 1.084, n = 0.2467;
  EXPECT_NEAR(normalized_curve(0.5, A, B, n), 0.853, 0.0005);
  EXPECT_NEAR(normalized_curve(1.0, A, B, n), 0.963, 0.0005);
  EXPECT_NEAR(normalized_curve(2.0, A, B, n), 1.045, 0.0005);
  EXPECT_NEAR(normalized_curve(3.0, A, B, n), 1.060, 0.0005);
  EXPECT_NEAR(normalized_curve(5.0, A, B, n), 1.009, 0.0005);
  // Eq. 15 at 0.1 % strain and 293 K with sigma_c = 32.8 MPa (Table 3): 19.75 MPa, a secant
  // modulus of 19.8 GPa (the form's infinite initial slope; physics.md section 6).
  EXPECT_NEAR(constitutive_stress(0.001, 293, 32.8e6, 2.357, 293, A, B, n) / 1e6, 19.75, 0.005);
}

TEST(NormalizedCurveLaw, FitRecoversNoiseFreeConstantsOnThePlateauWindow) {
  std::vector<double> e, s;
  for (double x = 0.5; x <= 3.0 + 1e-12; x += 0.05) {
    e.push_back(x);
    s.push_back(normalized_curve(x, -0.1206, 1.084, 0.2467));
  }
  const FitResult f = fit_normalized_curve(e, s);
  EXPECT_TRUE(f.converged) << f.note;
  EXPECT_NEAR(f["A"].value / -0.1206, 1.0, 1e-6);
  EXPECT_NEAR(f["B"].value / 1.084, 1.0, 1e-6);
  EXPECT_NEAR(f["n"].value / 0.2467, 1.0, 1e-6);
}
