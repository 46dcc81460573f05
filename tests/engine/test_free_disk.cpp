// A free elastic disk in flight with a non-uniform initial velocity (it translates, spins and
// vibrates): the mass is exact and the total momentum is conserved to round-off, because the
// internal forces at the nodes sum to zero (partition of unity) and FLIP/PIC transfers conserve
// momentum.
#include <cmath>
#include <limits>

#include <gtest/gtest.h>

#include "../deck_parts.hpp"
#include "scene_fixture.hpp"

using namespace pbx;

TEST(FreeDisk, MassExactMomentumConserved) {
  for (const char* integ : {"usl", "musl", "usf"}) {
    const std::string deck = std::string(R"(
[run]
end_time = "20 us"
history_points = 50
snapshots = 0
[grid]
cell_size = "10 um"
min = ["-0.05 mm", "-0.05 mm"]
max = ["0.45 mm", "0.45 mm"]
[solver]
integrator = ")") + integ + "\"\n" +
                             test::elastic("disk", 2.0, 1, 0.3) + test::disk_mm(0.15, 0.15, 0.08, "disk");
    Scene<2> sc = test::scene_from(deck);
    double m0 = 0;
    for (std::size_t p = 0; p < sc.particles.size(); ++p) {
      const Vec<2> r = sc.particles.x[p] - Vec<2>(0.15e-3, 0.15e-3);
      sc.particles.v[p] = Vec<2>(3.0 - 2e4 * r[1], 1.5 + 3e4 * r[0] + 1e8 * r[0] * r[0]);
      m0 += sc.particles.mass[p];
    }
    Runner<2> runner(sc, test::quiet());
    std::vector<Measurement> rows;
    runner.run([&](const Measurement& m) { rows.push_back(m); });
    ASSERT_GT(runner.solver().step_count(), 100);
    const double px0 = rows.front().momentum[0], py0 = rows.front().momentum[1];
    const double pnorm = std::hypot(px0, py0);
    for (auto& m : rows) {
      EXPECT_EQ(m.mass, rows.front().mass);
      EXPECT_NEAR(m.momentum[0], px0, 1e-12 * pnorm) << integ;
      EXPECT_NEAR(m.momentum[1], py0, 1e-12 * pnorm) << integ;
    }
    // the history sums strip by strip, m0 in one run: both within the rounding bound of a sum of
    // positive terms in any order, (n - 1) u sum
    const double u = 0.5 * std::numeric_limits<double>::epsilon();
    EXPECT_NEAR(rows.front().mass, m0, static_cast<double>(sc.particles.size() - 1) * u * m0);
    EXPECT_GT(rows.back().internal, 0.0);  // it did deform
  }
}
