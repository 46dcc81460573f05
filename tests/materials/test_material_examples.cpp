// The shipped parameter files load cleanly and carry the paper's numbers; the point driver's
// paths give the elastic constants they should.
#include <cmath>
#include <sstream>

#include <gtest/gtest.h>

#include "io/deck.hpp"
#include "materials/point_driver.hpp"

using namespace pbx;

namespace {
template <int D>
std::unique_ptr<Material<D>> example(const std::string& name, double T = 293.0) {
  const Deck deck = Deck::from_file(std::string(PBXMPM_EXAMPLES_DIR) + "/materials/" + name + ".toml");
  MaterialContext ctx;
  ctx.temperature = T;
  ctx.name = name;
  auto m = make_material<D>(deck.root().table("materials").table(name), ctx);
  deck.check_unused();
  return m;
}
}  // namespace

TEST(MaterialExamples, TatbTableOneAndItsWaveSpeed) {
  auto m = example<2>("tatb");
  EXPECT_EQ(m->model(), "j2_mie_gruneisen");
  EXPECT_DOUBLE_EQ(m->density(), 1934.0);
  // c_L = sqrt((rho0 c^2 + 4G/3)/rho0) = 3661 m/s (notes/physics.md 3.2)
  EXPECT_NEAR(m->initial_wave_speed(), std::sqrt((1934.0 * 2340.0 * 2340.0 + 4.0 / 3.0 * 11.5e9) / 1934.0), 1e-9);
  EXPECT_NEAR(m->initial_wave_speed(), 3661.0, 1.0);
  // each phase starts stress-free at its own rho0(T)
  EXPECT_NEAR(example<2>("tatb", 373.0)->density(), 1934.0 * std::exp(-3e-4 * 80.0), 1e-9);
}

TEST(MaterialExamples, F2314CalibrationSoftensWithTemperature) {
  // Secant shear modulus at 2.5 % shear strain at 250 /s (100 us): notes/physics.md 4.2 table.
  const double T[] = {293, 333, 353, 373}, G_expected[] = {68.6e6, 41.9e6, 30.8e6, 21.2e6};
  for (int i = 0; i < 4; ++i) {
    auto m = example<3>("f2314", T[i]);
    PointLoad load;
    load.path = PointPath::simple_shear, load.strain = 0.025, load.rate = 250.0, load.steps = 200;
    const auto out = drive_point(*m, load);
    EXPECT_NEAR(out.back().stress.xy / 0.025, G_expected[i], 0.01 * G_expected[i]) << T[i];
  }
}

TEST(MaterialExamples, UniaxialStressOfAnElasticSolidGivesYoungsModulus) {
  const Deck deck = Deck::from_string(
      "[materials.e]\nmodel = \"elastic_linear\"\ndensity = 1000.0\nbulk_modulus = 3e9\nshear_modulus = 1e9\n");
  MaterialContext ctx;
  auto m = make_material<3>(deck.root().table("materials").table("e"), ctx);
  PointLoad load;
  load.path = PointPath::uniaxial_stress, load.strain = -1e-4, load.rate = 1.0, load.steps = 20;
  const auto out = drive_point(*m, load);
  const double E = 9 * 3e9 * 1e9 / (3 * 3e9 + 1e9);
  EXPECT_NEAR(out.back().stress.xx / out.back().strain, E, 1e-4 * E);  // small strain: hypoelastic ~ linear
  EXPECT_NEAR(out.back().stress.yy, 0.0, 1e-6 * E * 1e-4);
  EXPECT_NEAR(out.back().stress.zz, 0.0, 1e-6 * E * 1e-4);
  std::ostringstream csv;
  write_point_csv(csv, out);
  EXPECT_EQ(csv.str().substr(0, 26), "time_s,strain,volume_ratio");
}

// The engine writes history variables by name: one name per stored double, in 2D and 3D.
TEST(MaterialExamples, HistoryNamesMatchHistorySize) {
  for (const char* name : {"tatb", "f2314"}) {
    auto m2 = example<2>(name);
    auto m3 = example<3>(name);
    EXPECT_EQ(static_cast<int>(m2->history_names().size()), m2->history_size()) << name;
    EXPECT_EQ(static_cast<int>(m3->history_names().size()), m3->history_size()) << name;
  }
  EXPECT_EQ(example<2>("tatb")->history_size(), 4);    // plastic strain + E, J, p
  EXPECT_EQ(example<2>("f2314")->history_size(), 24);  // 8 branches x (m, d, xy)
  EXPECT_EQ(example<3>("f2314")->history_size(), 48);  // 8 branches x 6
}

// The per-step wave speed that sets the stable time step follows the current tangent: TATB
// compressed hydrostatically to J = 0.9 (no yield) reports sqrt((K_tan + 4G/3) / rho) at the
// current density, with K_tan = -J dp/dJ of the Mie-Grueneisen path (a finite difference). The
// unstressed value would be 16 % too small there, and the time step too large.
TEST(MaterialExamples, StepWaveSpeedFollowsTheCompressedTangent) {
  auto m = example<3>("tatb");
  MaterialPoint<3> mp(*m);
  const double rate = 100.0, dt = 1e-6;
  const Mat3 L = -rate / 3 * Mat3::Identity();  // hydrostatic: J falls by a factor exp(-rate dt) per step
  MaterialStepResult r;
  double p_prev = 0, J_prev = 1;
  while (mp.J() > 0.9) {
    J_prev = mp.J();
    p_prev = -(mp.stress().xx + mp.stress().yy + mp.stress().zz) / 3;
    r = mp.step(L, dt);
  }
  ASSERT_LT(std::abs(mp.stress().xx - mp.stress().yy), 1e-6 * std::abs(mp.stress().xx));
  const double J = mp.J(), p = -(mp.stress().xx + mp.stress().yy + mp.stress().zz) / 3;
  ASSERT_EQ(mp.plastic_strain(), 0.0);
  const double Kfd = -0.5 * (J + J_prev) * (p - p_prev) / (J - J_prev);
  const double rho = 1934.0 / J, G = 11.5e9;
  const double c = std::sqrt((Kfd + 4.0 / 3.0 * G) / rho);
  EXPECT_NEAR(r.max_wave_speed, c, 2e-3 * c);
  EXPECT_GT(r.max_wave_speed, 1.15 * m->initial_wave_speed());  // 4338 against 3661 m/s
}
