// Homogeneous elastic column in the die (uniaxial strain): the punch stress rises with slope
// M = K + 4G/3, the wall stress with lambda = K - 2G/3, so wall/punch = nu/(1 - nu); the volume
// average of particle stress equals the punch stress; the run is quasi-static (KE/IE < 5 %).
// The material is hypoelastic, so under uniaxial strain sigma = M ln(H0/H): slopes are taken
// against the logarithmic strain (at 4 % strain it differs from the engineering strain by 3 %).
#include <cmath>
#include <cstdio>

#include <fmt/format.h>
#include <gtest/gtest.h>

#include "core/error.hpp"

#include "block_deck.hpp"
#include "scene_fixture.hpp"

using namespace pbx;

namespace {
constexpr double K = 10.59e9, G = 11.5e9, M = K + 4 * G / 3, LAMBDA = K - 2 * G / 3;

struct Curve {
  std::vector<Measurement> rows;
  long steps = 0;
};

Curve run_block(double f, double end_strain, const char* integrator = "usl", const char* kernel = "ugimp") {
  Scene<2> sc = test::scene_from(test::block_deck(f, end_strain, integrator, kernel));
  Runner<2> r(sc, test::quiet());
  Curve c;
  r.run([&](const Measurement& m) { c.rows.push_back(m); });
  c.steps = r.solver().step_count();
  return c;
}

// least-squares slope of y(x) over rows with strain in [a, b]
double slope(const Curve& c, double a, double b, double (*y)(const Measurement&)) {
  double sx = 0, sy = 0, sxx = 0, sxy = 0, n = 0;
  for (auto& m : c.rows)
    if (m.strain >= a && m.strain <= b) {
      const double e = std::log(1.0 / (1.0 - m.strain));
      sx += e;
      sy += y(m);
      sxx += e * e;
      sxy += e * y(m);
      n += 1;
    }
  return (n * sxy - sx * sy) / (n * sxx - sx * sx);
}
double punch(const Measurement& m) { return m.punch_stress; }
double wall(const Measurement& m) { return m.wall_stress; }
}  // namespace

TEST(DieBlock, ConstrainedModulusLateralRatioAndQuasiStatic) {
  for (const char* integ : {"musl", "usl", "usf"}) {
    // Over 1-4 % strain the three integrators give the same slopes (M -0.32 %, lambda/M +0.12 %,
    // 2026-12-05). The lateral tolerance (1 %) is what catches a velocity gradient taken at the
    // wall nodes from velocities the wall's contact did not set: before USF and MUSL took L at
    // contact nodes from the final contact velocity (Solver::final_contact) their ratio drifted to
    // +2.3 % (USF) and +1.1 % (MUSL) over this window, and the window had been cut to 3.6 % to fit.
    Curve c = run_block(100, 0.04, integ);
    const double Mfit = slope(c, 0.01, 0.04, punch), Lfit = slope(c, 0.01, 0.04, wall);
    std::printf("%s: M %+.4f, lambda/M %+.4f (relative errors)\n", integ, Mfit / M - 1,
                (Lfit / Mfit) / (LAMBDA / M) - 1);
    EXPECT_NEAR(Mfit, M, 0.01 * M) << integ;
    EXPECT_NEAR(Lfit / Mfit, LAMBDA / M, 0.01 * LAMBDA / M) << integ;  // nu/(1-nu)
    for (auto& m : c.rows) {
      if (m.strain < 0.01) continue;
      EXPECT_NEAR(-m.mean_stress.yy, m.punch_stress, 0.01 * m.punch_stress) << integ << " at strain " << m.strain;
      EXPECT_LT(m.ke_ie, 0.05) << integ << " at strain " << m.strain;
    }
    // Energy balance of an elastic, frictionless run: the punch's work is the kinetic plus the
    // stored (stress) energy, nothing dissipated; the gap is the step's O(1/N) force-stress lag and
    // the PIC share of the FLIP blend (printed). A stress work booked twice or half would miss by 50 %+.
    const Measurement& e = c.rows.back();
    EXPECT_EQ(e.dissipated, 0.0) << integ;
    EXPECT_NEAR(e.kinetic + e.internal, e.punch_work, 0.005 * e.punch_work) << integ;  // measured 0.02-0.14 %
    std::printf("%s: (KE + IE - W)/W = %.3g at the end\n", integ,
                (e.kinetic + e.internal - e.punch_work) / e.punch_work);
  }
}

// The 3-D die (issue 28): the same column in a cavity 4 x 24 x 4 cells between four side walls, a
// floor and the punch (run.dimension = 3, die.depth). Uniaxial strain is the same state in 3-D, so the
// slopes are the same M and lambda within the same 1 %; the front and back walls carry sigma_zz =
// lambda eps like the left and right ones (a z wall missing, or a stress divided by the width
// instead of the face area, would be off by the ratio of the areas or by 100 %); the punch stress is
// the volume average (the punch force is the mean over a row's span, the particles' stress the state at
// its end: half a row of M x 1e-4 strain lags, 0.5 % at 1 % strain with 401 rows; 2 % with 101).
// Measured 2026-12-06: M +0.15 % / +0.03 %, lambda/M -0.19 % / -0.12 % (uGIMP / bspline2); the
// front/back walls equal the left/right ones. bspline2 without its clamp at the front and back walls
// fails the per-row front/back check (checked).
namespace {
void die_block_3d(const std::string& deck) {
  Scene<3> sc = test::scene_from<3>(deck);
  ASSERT_TRUE(sc.die);
  ASSERT_GE(sc.die->front, 0);
  ASSERT_GE(sc.die->back, 0);
  EXPECT_EQ(sc.bodies.size(), 6u);
  Runner<3> r(sc, test::quiet());
  Curve c;
  r.run([&](const Measurement& m) { c.rows.push_back(m); });
  const double Mfit = slope(c, 0.01, 0.04, punch), Lfit = slope(c, 0.01, 0.04, wall);
  std::printf("3-D: M %+.4f, lambda/M %+.4f (relative errors)\n", Mfit / M - 1, (Lfit / Mfit) / (LAMBDA / M) - 1);
  EXPECT_NEAR(Mfit, M, 0.01 * M);
  EXPECT_NEAR(Lfit / Mfit, LAMBDA / M, 0.01 * LAMBDA / M);
  const double area = 0.04e-3 * 0.04e-3;
  double ratio_sum = 0;
  int rows = 0;
  for (auto& m : c.rows) {
    if (m.strain < 0.01) continue;
    const double side = (0.24e-3 * (1 - m.strain)) * 0.04e-3;
    const double front = m.body_force[static_cast<std::size_t>(sc.die->front)][2] / side;
    const double back = -m.body_force[static_cast<std::size_t>(sc.die->back)][2] / side;
    EXPECT_NEAR(front, m.wall_stress, 0.01 * m.wall_stress) << "at strain " << m.strain;
    EXPECT_NEAR(back, m.wall_stress, 0.01 * m.wall_stress) << "at strain " << m.strain;
    // the column rings slowly (the volume average over the punch stress swings 1.018 -> 0.995 ->
    // 1.002 from 0.4 % to 4 %, 2026-12-06): each row within 2 %, their mean within 0.5 %
    EXPECT_NEAR(-m.mean_stress.yy, m.punch_stress, 0.02 * m.punch_stress) << "at strain " << m.strain;
    ratio_sum += -m.mean_stress.yy / m.punch_stress;
    ++rows;
    EXPECT_NEAR(m.punch_force / area, m.punch_stress, 1e-12 * m.punch_stress);
    EXPECT_LT(m.ke_ie, 0.05) << "at strain " << m.strain;
  }
  ASSERT_GT(rows, 100);
  EXPECT_NEAR(ratio_sum / rows, 1.0, 0.005);
}
}  // namespace

TEST(DieBlock, ThreeDimensionalDieGivesTheConstrainedModuli) {
  // examples/3d/die_block.toml (uGIMP): the example a user runs is the deck tested; and with
  // bspline2, whose basis is clamped at the four side walls and the floor (z too: without the z
  // clamp the front and back walls would take too little, as the x walls did in 2-D)
  for (const char* kernel : {"ugimp", "bspline2"}) {
    SCOPED_TRACE(kernel);
    std::string deck = test::slurp(PBXMPM_EXAMPLES_DIR "/3d/die_block.toml");
    ASSERT_FALSE(deck.empty());
    deck.insert(deck.find("[grid]\n") + 7, fmt::format("shape_function = \"{}\"\n", kernel));
    die_block_3d(deck);
  }
}

// die.depth belongs to a 3-D die: a 2-D deck that gives one is refused naming the key (a 2-D die is
// per metre of depth), and a 3-D die without it is refused too.
TEST(DieBlock, DepthIsRequiredInThreeDimensionsAndRefusedInTwo) {
  std::string two = test::block_deck(100, 0.01);
  two.insert(two.find("[die]\n") + 6, "depth = \"0.04 mm\"\n");
  try {
    test::scene_from(two);
    ADD_FAILURE() << "a 2-D die with a depth was accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("die.depth"), std::string::npos) << e.what();
  }
  std::string three = test::slurp(PBXMPM_EXAMPLES_DIR "/3d/die_block.toml");
  three.erase(three.find("depth = "), three.find('\n', three.find("depth = ")) + 1 - three.find("depth = "));
  try {
    test::scene_from<3>(three);
    ADD_FAILURE() << "a 3-D die without a depth was accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("depth"), std::string::npos) << e.what();
  }
}

// The run stops where the deck says: punch displacement / height = end_strain at the last row
// (the ramp's distance is counted right), and the ramp ends at ramp_strain (0.004).
TEST(DieBlock, RunEndsAtTheEndStrain) {
  Curve c = run_block(100, 0.01);
  ASSERT_FALSE(c.rows.empty());
  EXPECT_NEAR(c.rows.back().strain, 0.01, 1e-5);  // the last step may pass the end by < 1e-5
  for (auto& m : c.rows)
    if (m.punch_velocity > 0.3 * (1 - 1e-12)) {  // the first row at full speed: the ramp is over
      EXPECT_GE(m.strain, 0.004 * (1 - 1e-9));
      break;
    }
}

TEST(DieBlock, MassScalingKeepsTheCurveAndCutsSteps) {
  Curve c1 = run_block(1, 0.02), c100 = run_block(100, 0.02);
  EXPECT_NEAR(static_cast<double>(c1.steps) / c100.steps, 10.0, 0.5);
  for (std::size_t i = 0; i < c1.rows.size(); ++i) {
    if (c1.rows[i].strain < 0.008) continue;
    ASSERT_NEAR(c1.rows[i].strain, c100.rows[i].strain, 1e-3 * c1.rows[i].strain);
    EXPECT_NEAR(c100.rows[i].punch_stress, c1.rows[i].punch_stress, 0.01 * c1.rows[i].punch_stress)
        << "strain " << c1.rows[i].strain;
  }
}

// The die test at the second resolution (5 um cells, the default scheme): the shape function a die
// run accepts passes there too (measured: M 0.3 % low, wall/punch 0.2 % high; 10 um: 0.5 %, 0.2 %).
TEST(DieBlock, ConstrainedModulusAndLateralRatioAtHalfTheCellSize) {
  std::string deck = test::block_deck(100, 0.036);
  deck.replace(deck.find("cell_size = \"10 um\""), 19, "cell_size = \"5 um\"");
  Scene<2> sc = test::scene_from(deck);
  Runner<2> r(sc, test::quiet());
  Curve c;
  r.run([&](const Measurement& m) { c.rows.push_back(m); });
  const double Mfit = slope(c, 0.01, 0.036, punch), Lfit = slope(c, 0.01, 0.036, wall);
  EXPECT_NEAR(Mfit, M, 0.01 * M);
  EXPECT_NEAR(Lfit / Mfit, LAMBDA / M, 0.02 * LAMBDA / M);
}

// bspline2 in the die at two resolutions, to the tolerances of the uGIMP tests above. Its basis is
// clamped at the die's walls and floor (grid/shape.hpp); unclamped it gave lambda/M 7.1 % low and
// M 1.4 % low at 10 um (the node one cell inside a wall takes part of the wall's load), and these
// checks fail. Measured 2026-12-06: M -0.80 % / -0.46 %, lambda/M +0.35 % / +0.21 % at 10 / 5 um
// (the rest is the punch's face, which moves and is not clamped).
TEST(DieBlock, Bspline2PassesTheDieTestAtTwoResolutions) {
  for (const char* cell : {"10 um", "5 um"}) {
    std::string deck = test::block_deck(100, 0.036, "usl", "bspline2");
    deck.replace(deck.find("cell_size = \"10 um\""), 19, fmt::format("cell_size = \"{}\"", cell));
    Scene<2> sc = test::scene_from(deck);
    Runner<2> r(sc, test::quiet());
    Curve c;
    r.run([&](const Measurement& m) { c.rows.push_back(m); });
    const double Mfit = slope(c, 0.01, 0.036, punch), Lfit = slope(c, 0.01, 0.036, wall);
    std::printf("bspline2 at %s: M %+.4f, lambda/M %+.4f (relative errors)\n", cell, Mfit / M - 1,
                (Lfit / Mfit) / (LAMBDA / M) - 1);
    EXPECT_NEAR(Mfit, M, 0.01 * M) << cell;
    EXPECT_NEAR(Lfit / Mfit, LAMBDA / M, 0.01 * LAMBDA / M) << cell;
    // quasi-static: the particles' mean stress is the punch stress row by row within 1.5 % (measured
    // at most 1.09 / 1.19 % at 10 / 5 um, uGIMP 0.95 %: the ringing of the column), 1 % on average
    double mean_gap = 0;
    int rows = 0;
    for (auto& m : c.rows)
      if (m.strain >= 0.01) {
        EXPECT_NEAR(-m.mean_stress.yy, m.punch_stress, 0.015 * m.punch_stress) << cell << " at strain " << m.strain;
        mean_gap += -m.mean_stress.yy / m.punch_stress - 1;
        ++rows;
      }
    EXPECT_LT(std::abs(mean_gap / rows), 0.01) << cell;
    const Measurement& e = c.rows.back();
    EXPECT_NEAR(e.kinetic + e.internal, e.punch_work, 0.005 * e.punch_work) << cell;
  }
}

// Linear shapes fail in the die (measured 2026-12-04 and again 2026-12-06: the run inverts a
// particle at 1.5 % strain with 10 um cells, for every contact_cutoff from 0 to 1; M 15 % low
// before; with a face contact that keeps the top row in front of the punch, tried 2026-12-06, the run finishes
// but M is 32 % low from the bulk's cell crossings), and bspline2 is clamped only at the die's own walls: a run refuses
// linear beside any unilateral rigid body, and bspline2 beside a unilateral [[rigid]] body, naming the key and the
// reason, instead of giving a wrong modulus.
TEST(DieBlock, ShapeFunctionsThatFailTheDieTestAreRefused) {
  const std::string plate = R"(
[[rigid]]
name = "plate"
min = ["0 mm", "0.485 mm"]
max = ["0.04 mm", "0.495 mm"]
normal = [0, -1]
)";
  const std::vector<std::pair<std::string, std::string>> cases = {
      {test::block_deck(100, 0.01, "usl", "linear"), "linear"},
      {test::block_deck(100, 0.01, "usl", "bspline2") + plate, "bspline2"}};
  for (const auto& [deck, kernel] : cases) {
    try {
      test::scene_from(deck);
      ADD_FAILURE() << kernel << " was accepted";
    } catch (const InputError& e) {
      const std::string want = kernel == "linear"
                                   ? "grid.shape_function: 'linear' is refused in a run with rigid contact bodies"
                                   : "grid.shape_function: 'bspline2' is refused beside a unilateral [[rigid]] body";
      EXPECT_NE(std::string(e.what()).find(want), std::string::npos) << e.what();
    }
  }
  test::scene_from(test::block_deck(100, 0.01, "usl", "bspline2"));  // the die alone: accepted
}
