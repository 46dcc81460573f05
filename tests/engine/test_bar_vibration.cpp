// Axial vibration of a bar clamped at x = 0 and free at x = L (notes/physics.md §8.1):
// v(x, 0) = v0 sin(pi x / 2L) gives v_cm(t) = (2 v0 / pi) cos(w t), w = pi c / 2L, T = 4L/c.
// With nu = 0 the plane-strain bar is exactly 1-D (sigma_yy = lambda eps_xx = 0), and so is the
// 3-D bar of square section: the same closed form checks the 3-D engine (Solver<3>, Runner<3>,
// the 3-D deck path), with the same tolerances.
#include <cmath>

#include <gtest/gtest.h>

#include "scene_fixture.hpp"

using namespace pbx;

namespace {
template <int D = 2>
void run_bar(const std::string& kernel) {
  const double L = 25.0, E = 100.0, rho = 1.0, v0 = 0.1;
  const double c = std::sqrt(E / rho), T = 4 * L / c;  // 10 s
  // the 3-D deck: the same bar with a 1 m square section (z from 0 to 1)
  auto vec = [](const char* xy, const char* z) {
    return D == 2 ? std::string(xy) + "]" : std::string(xy) + ", " + z + "]";
  };
  const std::string deck = R"(
[run]
dimension = )" + std::to_string(D) +
                           R"(
end_time = 50.0
history_points = 2001
snapshots = 0
[grid]
cell_size = 0.5
shape_function = ")" + kernel +
                           R"("
particles_per_cell = 2
min = )" + vec("[-2.0, -2.0", "-2.0") +
                           R"(
max = )" + vec("[28.0, 3.0", "3.0") +
                           R"(
[solver]
integrator = "musl"
flip = 1.0
cfl = 0.4
[materials.bar]
model = "linear_elastic"
density = 1.0
youngs_modulus = 100.0
poisson_ratio = 0.0
[[geometry]]
min = )" + vec("[0.0, 0.0", "0.0") +
                           R"(
max = )" + vec("[25.0, 1.0", "1.0") +
                           R"(
material = "bar"
[[rigid]]
name = "clamp"
min = )" + vec("[-1.0, -1.0", "-1.0") +
                           R"(
max = )" + vec("[0.0, 2.0", "2.0") +
                           R"(
normal = )" + vec("[1.0, 0.0", "0.0") +
                           R"(
contact = "stick"
)";
  Scene<D> sc = test::scene_from<D>(deck);
  for (std::size_t p = 0; p < sc.particles.size(); ++p) {
    sc.particles.v[p] = Vec<D>::Zero();
    sc.particles.v[p][0] = v0 * std::sin(M_PI * sc.particles.x[p][0] / (2 * L));
  }
  Runner<D> runner(sc, test::quiet());
  std::vector<double> t, vcm, energy;
  runner.run([&](const Measurement& m) {
    t.push_back(m.t);
    vcm.push_back(m.com_velocity[0]);
    energy.push_back(m.kinetic + m.internal);
  });
  // period from the downward zero crossings of v_cm (linear interpolation)
  std::vector<double> crossings;
  for (std::size_t i = 1; i < t.size(); ++i)
    if (vcm[i - 1] > 0 && vcm[i] <= 0)
      crossings.push_back(t[i - 1] + (t[i] - t[i - 1]) * vcm[i - 1] / (vcm[i - 1] - vcm[i]));
  ASSERT_GE(crossings.size(), 5u);
  const double period = (crossings.back() - crossings.front()) / static_cast<double>(crossings.size() - 1);
  EXPECT_NEAR(period, T, 0.01 * T) << kernel;
  double amp = 0;
  for (double v : vcm) amp = std::max(amp, std::abs(v));
  const double amp_exact = 2 * v0 / M_PI;
  EXPECT_NEAR(amp, amp_exact, 0.02 * amp_exact) << kernel;
  const double e0 = 0.5 * rho * v0 * v0 * L / 2 * 1.0;  // 0.0625 J per m of depth (2-D), J for the 1 m^2 section (3-D)
  EXPECT_NEAR(energy.front(), e0, 0.01 * e0);
  double drift = 0;
  for (double e : energy) drift = std::max(drift, std::abs(e - energy.front()));
  EXPECT_LT(drift, 0.01 * e0) << kernel;
}
}  // namespace

TEST(BarVibration, UgimpPeriodAmplitudeEnergy) { run_bar("ugimp"); }
TEST(BarVibration, Bspline2PeriodAmplitudeEnergy) { run_bar("bspline2"); }
TEST(BarVibration, UgimpPeriodAmplitudeEnergyIn3D) { run_bar<3>("ugimp"); }
