// Tait EOS (paper Eq. 11): explicit inversion and temperature dependence of K0 and V0.
#include <cmath>

#include <gtest/gtest.h>

#include "materials/tait.hpp"
#include "material_fixtures.hpp"
#include "materials/point_driver.hpp"
#include "materials/prony_deviator.hpp"
#include "materials/solid.hpp"

using namespace pbx;

TEST(Tait, PressureIsTheInverseOfEquation11) {
  const double C = 0.08936, K0 = 0.27e9;
  const TaitEos eos(C, K0);
  const double B = C * K0;
  for (double p : {1e6, 1e7, 5e7, 1e8, 1e9, -1e6, -0.5 * B}) {
    const double J = 1.0 - C * std::log1p(p / B);  // Eq. 11: V/V0 = 1 - C ln(1 + p/B)
    EXPECT_NEAR(eos.pressure(J), p, 1e-12 * std::abs(p)) << p;
  }
  // zero-pressure tangent is K0, and J = 0.95 gives 18.1 MPa (notes/physics.md 4.2)
  double* none = nullptr;
  EXPECT_NEAR(eos.update(1.0, 0.0, none).bulk_modulus, K0, 1e-12 * K0);
  EXPECT_NEAR(eos.pressure(0.95), 18.1e6, 0.05e6);
}

TEST(Tait, BulkModulusAndReferenceVolumeFollowTemperature) {
  for (double T : {293.0, 333.0, 353.0, 373.0}) {
    auto m = test::material_from<2>(test::f2314_body, T);
    auto* s = dynamic_cast<const Solid<2, PronyDeviator, TaitEos>*>(m.get());
    ASSERT_NE(s, nullptr);
    const double K0 = 0.27e9 * std::exp(-4e-3 * (T - 293.0));
    EXPECT_NEAR(s->eos().K0(), K0, 1e-14 * K0);
    EXPECT_NEAR(s->eos().B(), 0.08936 * K0, 1e-14 * K0);
    // V0(T) = V0(293) exp(alpha_v (T - 293))  <=>  rho0(T) = 2020 exp(-alpha_v (T - 293))
    EXPECT_NEAR(m->density(), 2020.0 * std::exp(-4.5e-4 * (T - 293.0)), 1e-12 * 2020.0);
  }
}

// Through the composed material: a hydrostatic path returns exactly the Tait pressure of J.
TEST(Tait, HydrostaticPathOfTheBinderFollowsTait) {
  auto m = test::material_from<3>(test::f2314_body, 353.0);
  PointLoad load;
  load.path = PointPath::hydrostatic, load.strain = -0.05, load.rate = 250.0, load.steps = 50;
  const auto out = drive_point(*m, load);
  const double K0 = 0.27e9 * std::exp(-4e-3 * 60.0), B = 0.08936 * K0;
  for (const auto& s : out) {
    const double p = B * std::expm1((1.0 - s.J) / 0.08936);
    EXPECT_NEAR(-s.stress.mean(), p, 1e-9 * B);
    EXPECT_NEAR(s.stress.von_mises(), 0.0, 1e-9 * B);
  }
}

// The tangent away from J = 1 (where its factors are 1): K = -J dp/dJ, by finite difference.
TEST(Tait, TangentMatchesFiniteDifferenceUnderCompression) {
  const TaitEos eos(0.08936, 0.27e9);
  double* none = nullptr;
  for (double J : {0.97, 0.9, 0.8}) {
    const double dJ = 1e-7;
    const double K = eos.update(J, 0.0, none).bulk_modulus;
    const double fd = -J * (eos.pressure(J + dJ) - eos.pressure(J - dJ)) / (2 * dJ);
    EXPECT_NEAR(K, fd, 1e-6 * fd) << J;
    EXPECT_GT(K, 1.2 * 0.27e9) << J;  // stiffens under compression
  }
}
