// Mie-Grueneisen EOS (paper Eq. 9, LS-DYNA form) against the linear Us-up Hugoniot of TATB.
#include <cmath>

#include <gtest/gtest.h>

#include "core/error.hpp"
#include "materials/mie_gruneisen.hpp"
#include "material_fixtures.hpp"
#include "materials/point_driver.hpp"

using namespace pbx;

namespace {
MieGruneisenEos tatb_eos() {
  MieGruneisenEos::Params p;
  p.rho0 = 1934.0, p.c = 2340.0, p.s1 = 2.32, p.gamma0 = 1.60;
  return MieGruneisenEos(p, "tatb");
}
}  // namespace

// Hugoniot states Us = c + s1 up, rho = rho0 Us/(Us - up), pH = rho0 Us up,
// E = pH (1 - rho0/rho)/2 per unit reference volume: the EOS must return pH.
TEST(MieGruneisen, ReproducesTheLinearHugoniotToRoundOff) {
  const auto eos = tatb_eos();
  const double rho0 = 1934.0, c = 2340.0, s1 = 2.32;
  const double published_pH[] = {0.4974e9, 1.7615e9, 3.3845e9, 9.0124e9};  // notes/physics.md 3.2
  int i = 0;
  for (double up : {100.0, 300.0, 500.0, 1000.0}) {
    const double Us = c + s1 * up;
    const double rho = rho0 * Us / (Us - up);
    const double pH = rho0 * Us * up;
    const double E = 0.5 * pH * (1.0 - rho0 / rho);
    const double mu = rho / rho0 - 1.0;
    EXPECT_NEAR(eos.pressure(mu, E), pH, 1e-10 * pH) << "up = " << up;
    EXPECT_NEAR(pH, published_pH[i++], 1e-4 * pH);
  }
}

// Expansion (mu < 0): p = rho0 c^2 mu + gamma0 E, continuous in value and slope at mu = 0.
TEST(MieGruneisen, ExpansionBranchIsLinearInMuPlusGammaE) {
  const auto eos = tatb_eos();
  const double rho0c2 = 1934.0 * 2340.0 * 2340.0;
  for (double mu : {-0.001, -0.02, -0.1}) {
    for (double E : {0.0, 1e6, -2e5}) {
      EXPECT_NEAR(eos.pressure(mu, E), rho0c2 * mu + 1.60 * E, 1e-12 * rho0c2);
    }
  }
  // continuity of pressure and slope at mu = 0
  EXPECT_NEAR(eos.cold(1e-9), rho0c2 * 1e-9, 1e-6 * rho0c2 * 1e-9);
  EXPECT_NEAR(eos.cold(-1e-9), -rho0c2 * 1e-9, 1e-12 * rho0c2 * 1e-9);
  EXPECT_NEAR(eos.cold_slope(0.0), rho0c2, 1e-12 * rho0c2);
  EXPECT_NEAR(eos.cold_slope(1e-12), rho0c2, 1e-9 * rho0c2);
}

TEST(MieGruneisen, ColdSlopeMatchesFiniteDifferenceWithAllTerms) {
  MieGruneisenEos::Params p;
  p.rho0 = 1934.0, p.c = 2340.0, p.s1 = 2.32, p.s2 = -0.5, p.s3 = 0.3, p.gamma0 = 1.6, p.a = 0.4;
  const MieGruneisenEos eos(p, "x");
  for (double mu : {0.01, 0.1, 0.3}) {
    const double h = 1e-6;
    const double fd = (eos.cold(mu + h) - eos.cold(mu - h)) / (2 * h);
    EXPECT_NEAR(eos.cold_slope(mu), fd, 1e-7 * std::abs(fd)) << mu;
  }
}

// Compress to J = 0.85 and release along the same J sequence: the trapezoidal energy update is
// time-reversible, so E returns to zero (and p to zero) to round-off.
TEST(MieGruneisen, CompressReleaseCycleReturnsToZeroEnergy) {
  const auto eos = tatb_eos();
  double h[3];
  eos.init_history(h);
  const int n = 400;
  double Emax = 0;
  for (int i = 1; i <= n; ++i) {
    eos.update(1.0 - 0.15 * i / n, 0.0, h);
    Emax = std::max(Emax, h[0]);
  }
  EXPECT_GT(Emax, 1e7);  // J/m^3: the energy was substantial
  for (int i = n - 1; i >= 0; --i) eos.update(1.0 - 0.15 * i / n, 0.0, h);
  EXPECT_NEAR(h[0], 0.0, 1e-12 * Emax);
  EXPECT_NEAR(h[2], 0.0, 1e-12 * 1934.0 * 2340.0 * 2340.0);
}

// The energy follows dE = -p dJ: against a fine-step reference integration, and the isentropic
// tangent returned for the time step equals -J dp/dJ along the isentrope.
TEST(MieGruneisen, EnergyIsPressureWorkAndTangentIsIsentropic) {
  const auto eos = tatb_eos();
  double h[3];
  eos.init_history(h);
  double W = 0, pprev = 0, Jprev = 1.0;
  const int n = 20000;
  for (int i = 1; i <= n; ++i) {
    const double J = 1.0 - 0.2 * i / n;
    const auto r = eos.update(J, 0.0, h);
    W -= 0.5 * (pprev + r.pressure) * (J - Jprev);
    pprev = r.pressure, Jprev = J;
  }
  EXPECT_NEAR(h[0], W, 1e-12 * W);
  double g[3] = {h[0], h[1], h[2]};
  const double J = h[1], dJ = -1e-7;
  const auto r0 = eos.update(J, 0.0, g);
  const auto r1 = eos.update(J + dJ, 0.0, g);
  EXPECT_NEAR(r0.bulk_modulus, -J * (r1.pressure - r0.pressure) / dJ, 2e-5 * r0.bulk_modulus);
}

TEST(MieGruneisen, DenominatorLimitIsAnInstabilityNotAnInfinity) {
  const auto eos = tatb_eos();
  EXPECT_THROW(eos.cold(1.0 / (2.32 - 1.0) + 0.01), std::runtime_error);
}

// The material point driver stops past the fit too (the EOS now gives NaN there instead of
// throwing): one step of plane-strain compression to J = 0.5 (mu = 1 > 1/(2.32 - 1) = 0.758).
TEST(MieGruneisen, PointDriverPastTheFitStopsWithTheReason) {
  const auto m = pbx::test::material_from<2>(pbx::test::tatb_body);
  pbx::MaterialPoint<2> mp(*m);
  pbx::Mat<2> L = pbx::Mat<2>::Zero();
  L(0, 0) = std::log(0.5) / 1e-6;
  try {
    mp.step(L, 1e-6);
    FAIL() << "no error; stress xx = " << mp.stress().xx;
  } catch (const pbx::InstabilityError& e) {
    EXPECT_NE(std::string(e.what()).find("J = 0.5: compression mu = rho/rho0 - 1 = 1 beyond the limit"),
              std::string::npos)
        << e.what();
  }
}

// The tangent with a volume-corrected gamma (a != 0) and energy on the particle, against a
// finite difference along the isentrope (the test above has a = 0); and in expansion.
TEST(MieGruneisen, TangentWithGammaCorrectionAndInExpansion) {
  MieGruneisenEos::Params p;
  p.rho0 = 1934.0, p.c = 2340.0, p.s1 = 2.32, p.s2 = 0.1, p.s3 = 0.05, p.gamma0 = 1.60, p.a = 0.4;
  const MieGruneisenEos eos(p, "tatb");
  for (double Jend : {0.85, 1.05}) {
    double h[3];
    eos.init_history(h);
    for (int i = 1; i <= 4000; ++i) eos.update(1.0 + (Jend - 1.0) * i / 4000, 2e3, h);  // heat: E > 0 too
    ASSERT_GT(h[0], 0.0);
    double g[3] = {h[0], h[1], h[2]};
    const double J = h[1], dJ = 1e-7 * (Jend < 1 ? -1 : 1);
    const auto r0 = eos.update(J, 0.0, g);
    const auto r1 = eos.update(J + dJ, 0.0, g);
    EXPECT_NEAR(r0.bulk_modulus, -J * (r1.pressure - r0.pressure) / dJ, 2e-5 * r0.bulk_modulus) << "J = " << Jend;
  }
}

// Heat reaches the energy (per reference volume) only with dissipation_to_energy: at fixed volume
// E grows by the heat exactly and p by gamma times it; with the flag off neither moves.
TEST(MieGruneisen, HeatRaisesEnergyAndPressureOnlyWithTheFlag) {
  MieGruneisenEos::Params p;
  p.rho0 = 1934.0, p.c = 2340.0, p.s1 = 2.32, p.gamma0 = 1.60, p.a = 0.4;
  for (bool flag : {true, false}) {
    p.dissipation_to_energy = flag;
    const MieGruneisenEos eos(p, "tatb");
    double h[3];
    eos.init_history(h);
    const double J = 0.95;
    const auto r0 = eos.update(J, 0.0, h);
    const double E0 = h[0];
    const auto r1 = eos.update(J, 5e6, h);  // 5 MJ/m^3 at fixed J (dJ = 0)
    const double mu = 1.0 / J - 1.0;
    EXPECT_NEAR(h[0] - E0, flag ? 5e6 : 0.0, 1e-6) << flag;
    EXPECT_NEAR(r1.pressure - r0.pressure, flag ? (1.60 + 0.4 * mu) * 5e6 : 0.0, 1e-3) << flag;
  }
}
