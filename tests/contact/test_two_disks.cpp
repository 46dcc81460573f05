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
  double e0 = 0;                                        // kinetic energy at the first row, J/m
  double e_max = 0, e_end = 0;                          // KE + IE + dissipated: largest, last
  double d_end = 0;                                     // friction work booked, J/m
};

Outcome collide(const std::string& law, const std::string& lines = "") {
  Scene<2> sc = test::scene_from(test::two_disks_deck(law, "12 us", 60, lines));
  Runner<2> runner(sc, test::quiet());
  Outcome o;
  double p_scale = 0;
  auto disks = [&](double& gap, double& vl, double& vr) {
    double xl = -1e9, xr = 1e9, ml = 0, mr = 0, pl = 0, pr = 0;
    for (std::size_t p = 0; p < sc.particles.size(); ++p) {
      const bool left = sc.field_names[static_cast<std::size_t>(sc.particles.field[p])] == "left";
      const double x = sc.particles.x[p].x(), m = sc.particles.mass[p], v = sc.particles.v[p].x();
      if (left) {
        xl = std::max(xl, x);
        ml += m;
        pl += m * v;
      } else {
        xr = std::min(xr, x);
        mr += m;
        pr += m * v;
      }
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
    const double e = m.kinetic + m.internal + m.dissipated;
    if (o.e0 == 0) o.e0 = m.kinetic;
    o.e_max = std::max(o.e_max, e);
    o.e_end = e;
    o.d_end = m.dissipated;
    EXPECT_LT(std::hypot(m.momentum[0], m.momentum[1]), 1e-10 * p_scale) << law;
  });
  o.v_left = vl;
  o.v_right = vr;
  return o;
}
}  // namespace

// Both laws at 10 um cells (2026-12-05): the disks never overlap, no energy is created (KE + IE +
// friction work never exceeds the initial KE; a contact impulse with the wrong sign or overshooting
// the momentum exchange would add energy), and they rebound with a restitution coefficient
// e = (v_r - v_l)/40 m/s of 0.867 (frictionless) and 0.874 (Coulomb 0.3). e is not 1 because the
// nodal exchange is perfectly inelastic node by node: 25 % of the KE is lost in the impact and not
// booked in `dissipated` (docs/theory/contact.md); [0.80, 1] holds that loss below 36 %. In a
// symmetric head-on impact friction does no physical work (no relative slip on the plane of
// symmetry), so Coulomb must rebound like frictionless (measured 0.8 % apart; 2 % allowed), and the
// friction work it books (7.7 % of the KE, from contact normals tilted off the plane at the nodes
// around it) stays below 10 %.
namespace {
void check_rebound(const Outcome& o, const char* law) {
  EXPECT_GT(o.min_gap, 0.0) << law;
  EXPECT_LE(o.e_max, o.e0 * (1 + 2e-3)) << law;
  const double e = (o.v_right - o.v_left) / 40.0;
  EXPECT_GT(e, 0.80) << law;
  EXPECT_LE(e, 1.0) << law;
  EXPECT_GT(o.e_end, 0.70 * o.e0) << law;
  EXPECT_NEAR(o.v_left, -o.v_right, 1e-9 * std::abs(o.v_left)) << law;  // symmetric
  std::printf("%s: restitution %.4f, (KE + IE + D) end / start %.4f\n", law, e, o.e_end / o.e0);
}
}  // namespace

TEST(TwoDisks, FrictionlessAndCoulombRebound) {
  const Outcome f = collide("frictionless"), c = collide("coulomb", "friction = 0.3\n");
  check_rebound(f, "frictionless");
  check_rebound(c, "coulomb");
  EXPECT_NEAR(c.v_right / f.v_right, 1.0, 0.02);
  EXPECT_EQ(f.d_end, 0.0);
  EXPECT_GT(c.d_end, 0.0);
  EXPECT_LT(c.d_end, 0.10 * c.e0);
}
