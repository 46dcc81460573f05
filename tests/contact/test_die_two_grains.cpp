// Die compression of a small two-grain + binder specimen: two stiff grains on two fields (colours)
// touching each other, a soft binder field around them, Coulomb mu = 0.3 between every pair of
// fields and at the die walls. After the punch ramp, in every history row,
//   punch force = bottom and side wall forces + rate of change of the specimen's momentum
// within 1 % of the punch force (y), and the x forces balance the x momentum change to 1 % of it:
// contact between fields exchanges momentum only inside the specimen, so the rigid-body reactions
// are the only external forces. The grain-grain and grain-binder contacts carry load, and every
// face and pair obeys mu = 0.3 (the side walls at the cap).
#include <cmath>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "../deck_parts.hpp"
#include "../engine/scene_fixture.hpp"

using namespace pbx;

namespace {
const std::string kDeck = R"(
[run]
end_strain = 0.01
history_points = 41
snapshots = 0
[grid]
cell_size = "10 um"
[solver]
mass_scaling = 100
[die]
width = "0.2 mm"
height = "0.24 mm"
punch_velocity = "0.3 m/s"
ramp_strain = 0.002
wall_friction = 0.3
[materials.tatb]
model = "linear_elastic"
density = "1.934 g/cm3"
bulk_modulus = "10.59 GPa"
shear_modulus = "11.5 GPa"
[materials.binder]
model = "linear_elastic"
density = "2.02 g/cm3"
youngs_modulus = "1 GPa"
poisson_ratio = 0.4
[contact]
default = "coulomb"
friction = 0.3
)" + test::two_grains_in_binder(0.045, "tatb", "binder");

// The deck with the shape function the die accepts besides the default (bspline2, clamped at the
// die's walls): every check below holds for both.
std::string with_shape(std::string deck, const std::string& kernel) {
  deck.replace(deck.find("[grid]\n"), 7, "[grid]\nshape_function = \"" + kernel + "\"\n");
  return deck;
}
}  // namespace

void check_two_grains(const std::string& deck);

TEST(DieTwoGrains, PunchForceEqualsWallForcesPlusMomentumRate) {
  for (const std::string kernel : {"ugimp", "bspline2"}) {
    SCOPED_TRACE(kernel);
    check_two_grains(with_shape(kDeck, kernel));
  }
}

void check_two_grains(const std::string& deck) {
  Scene<2> sc = test::scene_from(deck);
  ASSERT_TRUE(sc.die);
  const Die die = *sc.die;
  Runner<2> runner(sc, test::quiet());
  ASSERT_EQ(runner.contact_pairs().size(), 2u);  // binder_tatb, tatb_tatb
  std::vector<Measurement> rows;
  runner.run([&](const Measurement& m) { rows.push_back(m); });
  ASSERT_GT(rows.size(), 30u);
  double worst_y = 0, worst_x = 0;
  for (std::size_t k = 1; k < rows.size(); ++k) {
    const Measurement& m = rows[k];
    if (m.strain < 2 * die.ramp_strain) continue;
    const double span = m.t - rows[k - 1].t;
    double walls_y = 0, all_x = 0;
    for (int b : {die.left, die.right, die.bottom}) walls_y += m.body_force[static_cast<std::size_t>(b)][1];
    for (auto& f : m.body_force) all_x += f[0];
    const double dpy = (m.momentum[1] - rows[k - 1].momentum[1]) / span;
    const double dpx = (m.momentum[0] - rows[k - 1].momentum[0]) / span;
    // punch force (compression positive) = walls pushing up + (-) the rate of downward momentum
    const double residual_y = m.punch_force - (walls_y - dpy);
    EXPECT_LT(std::abs(residual_y), 0.01 * m.punch_force) << "strain " << m.strain;
    EXPECT_LT(std::abs(all_x - dpx), 0.01 * m.punch_force) << "strain " << m.strain;
    worst_y = std::max(worst_y, std::abs(residual_y) / m.punch_force);
    worst_x = std::max(worst_x, std::abs(all_x - dpx) / m.punch_force);
  }
  std::printf("die, two grains + binder: |punch - walls - dp/dt| / punch <= %.2e (y), %.2e (x)\n", worst_y, worst_x);

  // Coulomb mu = 0.3 at every rigid face and between every pair of fields. Each node obeys
  // |dp_t| <= mu |dp_n| with one sign of dp_n per face, so the summed tangential force of a face is
  // at most mu times its normal force (round-off: 1e-9), and so is a pair's summed |f_t| against its
  // summed |f_n|. The side walls see the specimen slide down along them (the column shortens), so
  // their friction is at the cap over most of the wall: the ratio must come close to mu, which a
  // friction law that ignored the coefficient (or a frictionless wall) would not give. The pairs
  // mostly stick here, so for them this is a bound only (checked: a field friction 1.5 mu passes
  // it); the field law reaching mu when sliding is BilayerShear.CoulombShearNeverExceedsMuTimesNormal.
  const double mu = 0.3;
  double side_ratio_max = 0;
  for (const Measurement& m : rows) {
    if (m.strain < 2 * die.ramp_strain) continue;
    const auto& L = m.body_force[static_cast<std::size_t>(die.left)];
    const auto& R = m.body_force[static_cast<std::size_t>(die.right)];
    const auto& B = m.body_force[static_cast<std::size_t>(die.bottom)];
    const auto& P = m.body_force[static_cast<std::size_t>(die.punch)];
    EXPECT_LE(std::abs(L[1]), mu * L[0] * (1 + 1e-9)) << "left wall, strain " << m.strain;
    EXPECT_LE(std::abs(R[1]), mu * -R[0] * (1 + 1e-9)) << "right wall, strain " << m.strain;
    EXPECT_LE(std::abs(B[0]), mu * B[1] * (1 + 1e-9)) << "bottom, strain " << m.strain;
    EXPECT_LE(std::abs(P[0]), mu * -P[1] * (1 + 1e-9)) << "punch, strain " << m.strain;
    // the walls hold the specimen up: friction on it points up (+y) on both sides
    EXPECT_GT(L[1], 0.0) << "strain " << m.strain;
    EXPECT_GT(R[1], 0.0) << "strain " << m.strain;
    side_ratio_max = std::max(side_ratio_max, (L[1] + R[1]) / (L[0] - R[0]));
    for (const auto& pf : m.pair_force) EXPECT_LE(pf[1], mu * pf[0] * (1 + 1e-9)) << "strain " << m.strain;
  }
  EXPECT_GT(side_ratio_max, 0.8 * mu);
  std::printf("side walls: friction / normal force up to %.3f (mu %.1f)\n", side_ratio_max, mu);
  // the grains really are in contact with each other and with the binder at the end
  const Measurement& last = rows.back();
  EXPECT_GT(last.punch_force, 0.0);
  EXPECT_GT(last.pair_force.at(0)[0], 0.05 * last.punch_force);  // binder_tatb normal
  EXPECT_GT(last.pair_force.at(1)[0], 0.0);                      // tatb_tatb normal
  std::printf("punch %.4g N/m, binder-tatb fn %.4g, tatb-tatb fn %.4g N/m\n", last.punch_force, last.pair_force[0][0],
              last.pair_force[1][0]);
}

// Energy where grain fields meet the die walls, at the paper decks' step (20 um cells, cfl 0.4,
// mass scaling 10, ramp 0.05 %): a small packed specimen (0.4 x 0.48 mm, grains 50-160 um, seed 3,
// the paper's 95:5 coats), frictionless, both phases linear elastic. Nothing in the run makes
// energy, so kinetic energy plus stress work stay below the punch work (short of it by the nodal
// exchange's losses: 0.77 at 0.4 % strain). With the walls acting before the fields' exchange
// after the grid update (until 2026-12-05) a field left the exchange moving into the wall and the
// particles there were squeezed a little more every step: 3.18 by 0.4 % strain on this specimen
// (1.26 with seed 2; 2.2 on the paper's 1.0 x 1.2 mm specimen by 0.3 %).
TEST(DieTwoGrains, GrainsAtTheWallsMakeNoEnergy) {
  const char* deck = R"(
[run]
end_strain = 0.004
history_points = 20
snapshots = 0
[grid]
cell_size = "20 um"
[solver]
mass_scaling = 10
cfl = 0.4
flip = 0.99
[die]
width = "0.4 mm"
height = "0.48 mm"
punch_velocity = "0.3 m/s"
ramp_strain = 0.0005
[specimen]
grain_material = "tatb"
binder_material = "f2314"
grain_fields = "colours"
seed = 3
[contact]
default = "frictionless"
[packing]
box = ["0.4 mm", "0.48 mm"]
porosity = 0.12
diameter_min = "50 um"
diameter_max = "160 um"
[packing.coarse]
mean = "130 um"
spread = "20 um"
share = 0.75
[packing.fine]
mean = "60 um"
spread = "20 um"
share = 0.25
[materials.tatb]
model = "linear_elastic"
density = "1.934 g/cm3"
bulk_modulus = "12.7 GPa"
shear_modulus = "11.5 GPa"
[materials.f2314]
model = "linear_elastic"
density = "2.02 g/cm3"
bulk_modulus = "0.27 GPa"
shear_modulus = "0.07 GPa"
)";
  for (const std::string kernel : {"ugimp", "bspline2"}) {
    Scene<2> sc = test::scene_from(with_shape(deck, kernel));
    Runner<2> runner(sc, test::quiet());
    double worst = 0;
    runner.run([&](const Measurement& m) {
      if (m.strain < 0.001 || !(m.punch_work > 0)) return;
      const double r = (m.kinetic + m.internal) / m.punch_work;
      worst = std::max(worst, r);
      EXPECT_LT(r, 1.0) << kernel << " at strain " << m.strain;
    });
    EXPECT_GT(worst, 0.5) << kernel;  // the balance is read at all
    std::printf("grains at the walls, %s: (KE + stress work) / punch work <= %.4f\n", kernel.c_str(), worst);
  }
}
