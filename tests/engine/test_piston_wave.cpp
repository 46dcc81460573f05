// A piston driven at constant speed v into a TATB column (paper Table 1: J2 + Mie-Grueneisen) in
// the die (uniaxial strain): behind the elastic front the stress is rho0 c_L v, with
// c_L = sqrt((rho0 c^2 + 4G/3)/rho0) = 3661 m/s, and the front reaches the bottom wall after H/c_L,
// where the reflection doubles the stress (notes/physics.md 8.2). In the 2-D die and in the 3-D die
// (a wave speed check of the 3-D kernels and the 3-D die's faces).
#include <cmath>
#include <fstream>
#include <sstream>

#include <gtest/gtest.h>

#include "scene_fixture.hpp"

using namespace pbx;

namespace {
// The column in the 2-D die, or (three_d) in the 3-D die with a 4-cell depth: the same uniaxial
// strain, so the same stress and arrival time (the 3-D die's face areas and walls, the 3-D kernels).
template <int D>
void piston_wave() {
  std::ifstream f(std::string(PBXMPM_EXAMPLES_DIR) + "/materials/tatb.toml");
  ASSERT_TRUE(f) << "examples/materials/tatb.toml";
  std::stringstream tatb;
  tatb << f.rdbuf();
  const double H = 0.96e-3, v = 1.0, rho0 = 1934, c = 2340, G = 11.5e9;
  const double cL = std::sqrt((rho0 * c * c + 4 * G / 3) / rho0);
  const double t_arrival = H / cL, sigma = rho0 * cL * v;
  const std::string deck = std::string(D == 3 ? "[run]\ndimension = 3\n" : "[run]\n") + R"(end_strain = 5.0e-4
history_points = 400
snapshots = 0
[grid]
cell_size = "10 um"
[solver]
cfl = 0.4
[die]
width = "0.04 mm"
height = "0.96 mm"
punch_velocity = "1 m/s"
ramp_strain = 0.0
)" + (D == 3 ? "depth = \"0.04 mm\"\n" : "") +
                           R"([[geometry]]
min = ["0 mm", "0 mm")" + (D == 3 ? ", \"0 mm\"" : "") +
                           R"(]
max = ["0.04 mm", "0.96 mm")" +
                           (D == 3 ? ", \"0.04 mm\"" : "") + R"(]
material = "tatb"
)" + tatb.str();
  Scene<D> sc = test::scene_from<D>(deck);
  ASSERT_GT(sc.control.end_time, 1.5 * t_arrival);
  Runner<D> r(sc, test::quiet());
  std::vector<Measurement> rows;
  r.run([&](const Measurement& m) { rows.push_back(m); });
  // punch stress while only the incident wave exists: 0.3 .. 0.9 of the transit time
  double sum = 0;
  int n = 0;
  for (auto& m : rows)
    if (m.t > 0.3 * t_arrival && m.t < 0.9 * t_arrival) {
      sum += m.punch_stress;
      ++n;
    }
  ASSERT_GT(n, 10);
  EXPECT_NEAR(sum / n, sigma, 0.02 * sigma) << D << "-D";
  // arrival: the bottom-wall stress first reaches the incident stress (half of the reflected 2 sigma)
  const double floor_area = D == 3 ? 0.04e-3 * 0.04e-3 : 0.04e-3;
  double t_hit = -1;
  for (auto& m : rows)
    if (m.wall_bottom / floor_area >= sigma) {
      t_hit = m.t;
      break;
    }
  ASSERT_GT(t_hit, 0);
  EXPECT_NEAR(t_hit, t_arrival, 0.05 * t_arrival) << D << "-D";
}
}  // namespace

TEST(PistonWave, ElasticWaveStressAndArrivalInTatb) { piston_wave<2>(); }

TEST(PistonWave, ElasticWaveStressAndArrivalInTatbInTheThreeDimensionalDie) { piston_wave<3>(); }
