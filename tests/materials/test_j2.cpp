// J2 + Cowper-Symonds deviator (paper Eq. 8): yield in uniaxial strain, perfect plasticity, the
// analytic hardening tangent, the rate factor, and objectivity under a rigid rotation.
#include <cmath>

#include <fmt/format.h>
#include <gtest/gtest.h>

#include "material_fixtures.hpp"
#include "materials/point_driver.hpp"

using namespace pbx;

namespace {
const double K = 10e9, G = 11.5e9, sigma0 = 0.8e9;

std::string j2_body(double Ep = 0.0, double beta = 1.0, double C = 0.0, double P = 0.0) {
  return fmt::format(R"(
model = "j2_linear"
density = 1934.0
bulk_modulus = {}
shear_modulus = {}
yield_stress = {}
hardening_modulus = {}
hardening_beta = {}
cowper_symonds_c = {}
cowper_symonds_p = {}
)",
                     K, G, sigma0, Ep, beta, C, P);
}

// Plane-strain uniaxial strain along x at rate `rate`, n steps to `strain`; returns the history.
std::vector<PointSample> uniaxial_strain_2d(const Material<2>& m, double strain, double rate, int n) {
  MaterialPoint<2> mp(m);
  std::vector<PointSample> out;
  const double dt = std::abs(strain / rate) / n;
  Mat<2> L = Mat<2>::Zero();
  L(0, 0) = strain > 0 ? rate : -rate;
  for (int i = 0; i < n; ++i) {
    mp.step(L, dt);
    PointSample s;
    s.strain = std::log(mp.F()(0, 0));
    s.stress = mp.stress();
    s.plastic_strain = mp.plastic_strain();
    s.J = mp.J();
    out.push_back(s);
  }
  return out;
}
}  // namespace

TEST(J2, UniaxialStrainYieldsWhereAxialMinusLateralEqualsYieldStress) {
  auto m = test::material_from<2>(j2_body());
  const auto out = uniaxial_strain_2d(*m, -0.06, 250.0, 600);
  const double eps_y = sigma0 / (2.0 * G);  // 2 G |eps| = sigma0 in uniaxial strain
  bool yielded = false;
  for (const auto& s : out) {
    const double diff = s.stress.yy - s.stress.xx;  // lateral - axial (compression: axial more negative)
    EXPECT_NEAR(s.stress.yy, s.stress.zz, 1e-6);    // plane strain keeps sigma_zz = lateral
    if (std::abs(s.strain) < eps_y - 1e-4) {
      EXPECT_EQ(s.plastic_strain, 0.0);
      EXPECT_NEAR(diff, 2.0 * G * std::abs(s.strain), 1e-9 * sigma0);
      // elastic: axial = (K + 4G/3) eps, lateral = (K - 2G/3) eps with eps = ln J
      EXPECT_NEAR(s.stress.xx, (K + 4.0 * G / 3.0) * s.strain, 1e-9 * sigma0);
    } else if (std::abs(s.strain) > eps_y + 1e-4) {
      yielded = true;
      EXPECT_GT(s.plastic_strain, 0.0);
      // perfectly plastic: stays on the yield surface
      EXPECT_NEAR(diff, sigma0, 1e-12 * sigma0);
      EXPECT_NEAR(s.stress.von_mises(), sigma0, 1e-12 * sigma0);
      // plastic strain = (2/3)(|eps| - eps_y) for uniaxial strain with a perfectly plastic law
      EXPECT_NEAR(s.plastic_strain, 2.0 / 3.0 * (std::abs(s.strain) - eps_y), 1e-9);
    }
  }
  EXPECT_TRUE(yielded);
}

TEST(J2, PerfectPlasticityStaysOnTheYieldSurfaceUnderMixedLoading) {
  auto m = test::material_from<3>(j2_body());
  MaterialPoint<3> mp(*m);
  Mat3 L = Mat3::Zero();
  L(0, 0) = -250, L(0, 1) = 400, L(1, 2) = -150, L(2, 2) = 100;
  int plastic_steps = 0;
  for (int i = 0; i < 400; ++i) {
    mp.step(L, 1e-6);
    if (mp.plastic_strain() > 0) {
      ++plastic_steps;
      EXPECT_NEAR(mp.stress().von_mises(), sigma0, 1e-12 * sigma0);
    }
  }
  EXPECT_GT(plastic_steps, 100);
}

// Uniaxial strain with linear hardening H: tangent d sigma_axial / d eps = K + (4/3) G H/(3G + H),
// for isotropic (beta = 1) and kinematic (beta = 0) hardening alike under monotonic loading.
TEST(J2, LinearHardeningGivesTheAnalyticTangent) {
  const double H = 2e9;
  for (double beta : {1.0, 0.0, 0.5}) {
    auto m = test::material_from<2>(j2_body(H, beta));
    const auto out = uniaxial_strain_2d(*m, -0.08, 250.0, 800);
    const auto& a = out[600];
    const auto& b = out[799];
    ASSERT_GT(a.plastic_strain, 0.0);
    const double tangent = (b.stress.xx - a.stress.xx) / (b.strain - a.strain);
    EXPECT_NEAR(tangent, K + 4.0 / 3.0 * G * H / (3.0 * G + H), 1e-9 * K) << "beta = " << beta;
    // the yield stress grows by H times the plastic strain (isotropic part beta H, back stress (1-beta) H)
    EXPECT_NEAR(b.stress.yy - b.stress.xx, sigma0 + H * b.plastic_strain, 1e-9 * sigma0) << beta;
  }
}

// Cowper-Symonds: sigma_y = sigma0 [1 + (epsdot/C)^(1/P)]; in uniaxial strain the equivalent
// deviatoric strain rate is (2/3) |eps_dot|. C = 0 switches the factor off.
TEST(J2, CowperSymondsFactorAtAGivenRate) {
  const double C = 40.0, P = 5.0, rate = 3000.0;
  auto m = test::material_from<2>(j2_body(0.0, 1.0, C, P));
  const auto out = uniaxial_strain_2d(*m, -0.2, rate, 400);  // yields at ~11 %
  const double factor = 1.0 + std::pow(2.0 / 3.0 * rate / C, 1.0 / P);
  EXPECT_NEAR(out.back().stress.yy - out.back().stress.xx, sigma0 * factor, 1e-10 * sigma0);
  auto off = test::material_from<2>(j2_body(0.0, 1.0, 0.0, 0.0));
  const auto o2 = uniaxial_strain_2d(*off, -0.08, rate, 400);
  EXPECT_NEAR(o2.back().stress.yy - o2.back().stress.xx, sigma0, 1e-10 * sigma0);
}

// Jaumann + Hughes-Winget: a stressed point rotated rigidly by 90 degrees in many steps carries
// the rotated stress (1e-6 relative), with the Mie-Grueneisen pressure unchanged (J constant).
template <int D>
void rigid_rotation_check() {
  auto m = test::material_from<D>(test::tatb_body);
  MaterialPoint<D> mp(*m);
  Mat<D> L = Mat<D>::Zero();
  L(0, 0) = -250.0, L(0, 1) = 100.0;  // compress and shear (elastic, well below yield)
  for (int i = 0; i < 50; ++i) mp.step(L, 1e-6);
  const Sym3 s0 = mp.stress();
  ASSERT_EQ(mp.plastic_strain(), 0.0);
  ASSERT_GT(s0.norm(), 1e7);
  const double omega = 2000.0, T = M_PI / 2 / omega;  // rad/s
  Mat<D> W = Mat<D>::Zero();
  W(0, 1) = -omega, W(1, 0) = omega;
  const int n = 2000;
  for (int i = 0; i < n; ++i) mp.step(W, T / n);
  Mat3 R = Mat3::Zero();
  R(0, 1) = -1, R(1, 0) = 1, R(2, 2) = 1;  // +90 degrees about z
  const Sym3 expected = rotate(s0, R);
  EXPECT_LT((mp.stress() - expected).norm(), 1e-6 * s0.norm()) << "D = " << D;
}
TEST(J2, RigidRotationOfAStressedPointIsObjective2D) { rigid_rotation_check<2>(); }
TEST(J2, RigidRotationOfAStressedPointIsObjective3D) { rigid_rotation_check<3>(); }

// Plastic work goes to the energy bookkeeping: with perfect plasticity the dissipation rate is
// sigma0 times the equivalent plastic strain rate (per unit current volume).
TEST(J2, PlasticWorkIsReportedAsDissipation) {
  auto m = test::material_from<3>(j2_body());
  MaterialPoint<3> mp(*m);
  Mat3 L = Mat3::Zero();
  L(0, 1) = 1000.0;  // simple shear, J = 1
  double expected = 0, prev = 0;
  for (int i = 0; i < 300; ++i) {
    mp.step(L, 1e-6);
    expected += sigma0 * (mp.plastic_strain() - prev);
    prev = mp.plastic_strain();
  }
  ASSERT_GT(mp.plastic_strain(), 0.05);
  EXPECT_NEAR(mp.dissipated(), expected, 1e-9 * expected);
}

// With kinematic hardening (beta = 0) the yield surface keeps its size sigma0 and moves with the
// back stress: the dissipation (s - alpha) : d eps_p is sigma0 times the equivalent plastic strain
// increment, forward and in reverse flow. Booking the whole plastic work s : d eps_p (as before)
// gives 0.9 GPa per unit plastic strain forward at alpha_eq = 0.1 GPa and less than sigma0 in reverse.
TEST(J2, KinematicHardeningStoresTheBackStressWorkAndDissipatesTheRest) {
  auto m = test::material_from<3>(j2_body(2e9, 0.0));
  MaterialPoint<3> mp(*m);
  Mat3 L = Mat3::Zero();
  double expected = 0, prev = 0;
  for (int i = 0; i < 600; ++i) {
    L(0, 1) = i < 300 ? 1000.0 : -1000.0;  // simple shear forward, then back
    mp.step(L, 1e-6);
    expected += sigma0 * (mp.plastic_strain() - prev);
    prev = mp.plastic_strain();
    if (i == 299) {
      EXPECT_NEAR(mp.dissipated(), expected, 1e-6 * expected) << "end of the forward shear";
    }
  }
  ASSERT_GT(mp.plastic_strain(), 0.1);
  EXPECT_NEAR(mp.dissipated(), expected, 1e-6 * expected);
}
