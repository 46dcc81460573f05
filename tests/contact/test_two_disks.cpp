// Two elastic disks on separate fields colliding head-on at +-20 m/s: with a frictionless or
// Coulomb law they never interpenetrate (the plane x = midpoint separates them), total momentum is
// conserved to 1e-10 relative at every row, and they rebound. (The weld law does NOT make elastic
// disks stick: single-velocity MPM rebounds them too, as in Sulsky et al. 1994; not tested here.)
#include <algorithm>
#include <cmath>
#include <limits>

#include <gtest/gtest.h>

#include "../engine/scene_fixture.hpp"
#include "two_disks_deck.hpp"

using namespace pbx;

namespace {

struct Outcome {
  double min_gap = std::numeric_limits<double>::max();  // min x(right) - max x(left), m
  double v_left = 0, v_right = 0;                       // final mean x velocities, m/s
};

Outcome collide(const std::string& law) {
  Scene<2> sc = test::scene_from(test::two_disks_deck(law));
  Runner<2> runner(sc, test::quiet());
  Outcome o;
  double p_scale = 0;
  auto disks = [&](double& gap, double& vl, double& vr) {
    double xl = -1e9, xr = 1e9, ml = 0, mr = 0, pl = 0, pr = 0;
    for (std::size_t p = 0; p < sc.particles.size(); ++p) {
      const bool left = sc.field_names[static_cast<std::size_t>(sc.particles.field[p])] == "left";
      const double x = sc.particles.x[p].x(), m = sc.particles.mass[p], v = sc.particles.v[p].x();
      if (left) { xl = std::max(xl, x); ml += m; pl += m * v; }
      else { xr = std::min(xr, x); mr += m; pr += m * v; }
    }
    gap = xr - xl;
    vl = pl / ml;
    vr = pr / mr;
    p_scale = std::max(p_scale, std::abs(pl));
  };
  double g, vl, vr;
  disks(g, vl, vr);
  runner.run([&](const Measurement& m) {
    disks(g, vl, vr);
    o.min_gap = std::min(o.min_gap, g);
    EXPECT_LT(std::hypot(m.momentum[0], m.momentum[1]), 1e-10 * p_scale) << law;
  });
  o.v_left = vl;
  o.v_right = vr;
  return o;
}
}  // namespace

TEST(TwoDisks, FrictionlessRebounds) {
  const Outcome o = collide("frictionless");
  EXPECT_GT(o.min_gap, 0.0);
  EXPECT_LT(o.v_left, -5.0);  // rebounded
  EXPECT_GT(o.v_right, 5.0);
}
