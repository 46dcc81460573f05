// Generalized Maxwell deviator (paper Eq. 10) with the F2314 calibration: step relaxation,
// constant-rate loading against the analytic convolution, time-temperature superposition and the
// exactness of the exponential update and of its dissipation.
#include <cmath>

#include <gtest/gtest.h>

#include "materials/tait.hpp"
#include "material_fixtures.hpp"
#include "materials/point_driver.hpp"
#include "materials/prony_deviator.hpp"
#include "materials/solid.hpp"

using namespace pbx;

namespace {
const double G_inf = 10e6, Gk = 12.5e6;
double tau_k(int k) { return std::pow(10.0, k - 7); }  // k = 0..7: 1e-7 ... 1 s

double relaxation(double t, double aT = 1.0) {
  double g = G_inf;
  for (int k = 0; k < 8; ++k) g += Gk * std::exp(-t / (tau_k(k) * aT));
  return g;
}
// Constant deviatoric strain rate r: s(t) = 2 r [G_inf t + sum G_k tau_k (1 - exp(-t/tau_k))].
double ramp_integral(double t) {
  double g = G_inf * t;
  for (int k = 0; k < 8; ++k) g += Gk * tau_k(k) * -std::expm1(-t / tau_k(k));
  return g;
}
}  // namespace

// Step shear gamma0 = 1 %: tau(t) = gamma0 [G_inf + sum G_k exp(-t/tau_k)] within 0.5 % at six
// times spanning the series; also the tabulated values of notes/physics.md section 8.6.
TEST(Viscoelastic, StepShearRelaxation) {
  auto m = test::material_from<3>(test::f2314_body);
  MaterialPoint<3> mp(*m);
  const double g0 = 0.01, t_jump = 1e-13;
  Mat3 L = Mat3::Zero();
  L(0, 1) = g0 / t_jump;
  mp.step(L, t_jump);
  EXPECT_NEAR(mp.stress().xy, 1.100e6, 0.005 * 1.100e6);
  const Mat3 hold = Mat3::Zero();
  const double times[] = {1e-7, 1e-6, 1e-4, 1e-2, 1.0, 1e4};
  const double tabulated[] = {0, 0.883e6, 0.633e6, 0.383e6, 0.146e6, 0.100e6};
  for (int i = 0; i < 6; ++i) {
    mp.step(hold, times[i] - mp.time());
    const double expected = g0 * relaxation(times[i]);
    EXPECT_NEAR(mp.stress().xy, expected, 0.005 * expected) << "t = " << times[i];
    if (tabulated[i] > 0) {
      EXPECT_NEAR(mp.stress().xy, tabulated[i], 0.005 * tabulated[i]);
    }
  }
}

// Constant-rate pure shear (no spin): the exponential update is exact for a piecewise-constant
// rate, so any step size reproduces the convolution integral to round-off.
TEST(Viscoelastic, ConstantRatePureShearMatchesTheConvolutionExactly) {
  auto m = test::material_from<3>(test::f2314_body);
  const double r = 250.0;
  Mat3 L = Mat3::Zero();
  L(0, 0) = r, L(1, 1) = -r;
  for (int n : {1, 7, 1000}) {
    MaterialPoint<3> mp(*m);
    for (int i = 0; i < n; ++i) mp.step(L, 1e-4 / n);
    const double expected = 2.0 * r * ramp_integral(1e-4);
    EXPECT_NEAR(mp.stress().xx - mp.stress().mean(), expected, 1e-10 * expected) << n << " steps";
    EXPECT_NEAR(mp.stress().xy, 0.0, 1e-9);
  }
}

// Constant-rate simple shear: tau(t) = gamma_dot [G_inf t + sum G_k tau_k (1 - e^(-t/tau_k))]
// up to the O(gamma^2) effect of the spin (gamma <= 2.5 %).
TEST(Viscoelastic, ConstantRateSimpleShearMatchesTheConvolution) {
  auto m = test::material_from<3>(test::f2314_body);
  PointLoad load;
  load.path = PointPath::simple_shear, load.strain = 0.025, load.rate = 250.0, load.steps = 500;
  const auto out = drive_point(*m, load);
  for (std::size_t i = 50; i < out.size(); i += 50) {
    const double expected = 250.0 * ramp_integral(out[i].time);
    EXPECT_NEAR(out[i].stress.xy, expected, 1e-3 * expected) << out[i].time;
  }
  // G at the paper's loading time (100 us to 2.5 %): the calibration target G ~ 70 MPa
  EXPECT_NEAR(out.back().stress.xy / 0.025, 68.6e6, 0.5e6);
}

// Time-temperature superposition: at T the response equals the reference response with time
// scaled by a_T (1e-8 relative), for a ramp-and-hold history.
TEST(Viscoelastic, TemperatureScalesTimeByTheShiftFactor) {
  for (double T : {333.0, 353.0, 373.0}) {
    auto hot = test::material_from<3>(test::f2314_body, T);
    auto ref = test::material_from<3>(test::f2314_body, 293.0);
    const double aT = dynamic_cast<const Solid<3, PronyDeviator, TaitEos>&>(*hot).deviator().shift_factor();
    EXPECT_NEAR(aT, std::exp(100e3 / 8.31446261815324 * (1.0 / T - 1.0 / 293.0)), 1e-14);
    MaterialPoint<3> a(*hot), b(*ref);
    Mat3 L = Mat3::Zero();
    L(0, 0) = 250.0, L(1, 1) = -250.0;
    const int n = 40;
    for (int i = 0; i < n; ++i) {
      a.step(L, 1e-4 / n);
      b.step(L * aT, 1e-4 / aT / n);  // same strain; reference time = t / a_T
    }
    const Mat3 hold = Mat3::Zero();
    a.step(hold, 3e-4);
    b.step(hold, 3e-4 / aT);
    const double sa = a.stress().xx - a.stress().mean(), sb = b.stress().xx - b.stress().mean();
    EXPECT_NEAR(sa, sb, 1e-8 * std::abs(sb)) << T;
  }
  // WLF, log10 a_T = -C1 (T - Tref)/(C2 + T - Tref)
  const std::string wlf = test::f2314_body.substr(0, test::f2314_body.find("shift")) +
                          "shift = \"wlf\"\nwlf_c1 = 17.44\nwlf_c2 = \"51.6 K\"\ntait_c = 0.08936\ntait_k0 = 2.7e8\n";
  auto w = test::material_from<3>(wlf, 313.0);
  const double aw = dynamic_cast<const Solid<3, PronyDeviator, TaitEos>&>(*w).deviator().shift_factor();
  EXPECT_NEAR(std::log10(aw), -17.44 * 20.0 / (51.6 + 20.0), 1e-12);
}

// Dissipation: the closed form per step is exact for a constant rate (one step = many steps), and
// the energy balance work = stored + dissipated holds to the accuracy of the trapezoidal work.
TEST(Viscoelastic, DissipationIsExactAndBalancesTheWork) {
  auto m = test::material_from<3>(test::f2314_body);
  Mat3 L = Mat3::Zero();
  L(0, 0) = 250.0, L(1, 1) = -250.0;
  MaterialPoint<3> one(*m), many(*m);
  one.step(L, 1e-4);
  for (int i = 0; i < 20000; ++i) many.step(L, 1e-4 / 20000);
  EXPECT_NEAR(one.dissipated(), many.dissipated(), 1e-9 * many.dissipated());
  // stored energy: G_inf branch s_inf:s_inf/(4 G_inf) + sum h_k:h_k/(4 G_k)
  const auto& h = many.history();
  Sym3 s = many.stress().dev();
  double stored = 0;
  for (int k = 0; k < 8; ++k) {
    const Sym3 hk{h[6 * k], h[6 * k + 1], h[6 * k + 2], h[6 * k + 3], h[6 * k + 4], h[6 * k + 5]};
    stored += hk.ddot(hk) / (4.0 * Gk);
    s = s - hk;
  }
  stored += s.ddot(s) / (4.0 * G_inf);
  EXPECT_GT(many.dissipated(), 0.1 * stored);
  EXPECT_NEAR(many.stress_work(), stored + many.dissipated(), 1e-6 * many.stress_work());
}

// Optional bulk Prony terms: an instantaneous volumetric step adds sum K_j exp(-t/tauK_j) theta0 to
// the mean stress on top of the Tait pressure.
TEST(Viscoelastic, BulkPronyOverstressRelaxes) {
  auto m = test::material_from<3>(test::f2314_body +
                                  "prony_bulk_moduli = [\"40 MPa\", \"20 MPa\"]\nprony_bulk_times = [1e-5, 1e-3]\n");
  MaterialPoint<3> mp(*m);
  const double theta0 = -0.01, t_jump = 1e-13;
  mp.step(Mat3::Identity() * (theta0 / 3.0 / t_jump), t_jump);
  const TaitEos tait(0.08936, 0.27e9);
  for (double t : {1e-6, 1e-5, 1e-4, 1e-3, 1e-1}) {
    mp.step(Mat3::Zero(), t - mp.time());
    const double over = theta0 * (40e6 * std::exp(-t / 1e-5) + 20e6 * std::exp(-t / 1e-3));
    EXPECT_NEAR(mp.stress().mean(), -tait.pressure(mp.J()) + over, 1e-6 * 40e6 * 0.01) << t;
  }
}

// Plane strain uses a compact (m, d, xy) storage and a double-angle rotation of the Prony branches:
// it must agree with the full 3D update on an in-plane path with spin and volume change.
TEST(Viscoelastic, PlaneStrainMatchesThreeDimensionsOnInPlanePaths) {
  for (const std::string& body :
       {test::f2314_body, test::f2314_body + "prony_bulk_moduli = [\"40 MPa\"]\nprony_bulk_times = [1e-5]\n"}) {
    auto m2 = test::material_from<2>(body, 333.0);
    auto m3 = test::material_from<3>(body, 333.0);
    MaterialPoint<2> a(*m2);
    MaterialPoint<3> b(*m3);
    Mat<2> L2;
    L2 << -300.0, 800.0, -500.0, 120.0;
    Mat3 L3 = Mat3::Zero();
    L3.topLeftCorner<2, 2>() = L2;
    for (int i = 0; i < 300; ++i) {
      const double dt = (i % 3 + 1) * 1e-7;
      a.step(L2, dt);
      b.step(L3, dt);
    }
    const double scale = b.stress().norm();
    EXPECT_LT((a.stress() - b.stress()).norm(), 1e-12 * scale);
    EXPECT_NEAR(a.dissipated(), b.dissipated(), 1e-12 * b.dissipated());
  }
}

// The point driver's step_shear path (pbxmpm material --path step_shear) jumps in a step short
// against every relaxation time: its first sample is G(0) gamma0 also at 373 K with a 10 s hold,
// where F2314's fastest branch relaxes in 1e-7 s x a_T = 1.5e-11 s (the jump of 1e-12 x hold =
// 1e-11 s it used to take read 3 % low).
TEST(Viscoelastic, PointDriverStepShearJumpIsInstantaneousAtHighTemperature) {
  auto m = test::material_from<3>(test::f2314_body, 373.0);
  PointLoad load;
  load.path = PointPath::step_shear;
  load.strain = 0.01;
  load.duration = 10.0;
  load.steps = 50;
  const auto out = drive_point(*m, load);
  ASSERT_GE(out.size(), 2u);
  const double G0 = G_inf + 8 * Gk;
  EXPECT_NEAR(out[1].stress.xy, G0 * 0.01, 1e-3 * G0 * 0.01);
}
