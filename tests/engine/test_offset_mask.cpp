// The fused USL pass scatters the mass-centre offsets only for particles near a rigid body
// (Solver::mark_offset_bases): at every node where a body is present at the next step the sums
// must still equal those of a full P2G to the bit, and away from the bodies they must really be
// left out (else the test would not test the mask).
#include <gtest/gtest.h>

#include "block_deck.hpp"
#include "scene_fixture.hpp"

using namespace pbx;

namespace {
// mismatching offsets at body nodes over 300 steps; nodes checked with specimen mass; at the last
// step, nodes with mass whose offsets the pass left out, and nodes with mass
struct MaskCheck {
  long mismatches = 0, checked = 0, left_out = 0, with_mass = 0;
};

MaskCheck check_mask(const char* kernel) {
  // the die block 40 cells wide and 40 high, so most particles are far from the walls; the punch
  // at ten times the paper's speed moves about a cell in the 300 steps, so the stencil bases of
  // its rigid particles change during the test
  std::string deck = test::block_deck(100, 0.01, "usl", "ugimp", 0.4, 0.4);
  deck.replace(deck.find("\"0.3 m/s\""), 9, "\"3 m/s\"");
  Scene<2> sc = test::scene_from(deck);
  // The mask is a property of the kernel's support and the bodies' motion: it is checked on the die
  // block for bspline2 too, which a run deck refuses beside a die (its wall/punch ratio; see
  // DieBlock.ShapeFunctionsThatFailTheDieTestAreRefused), so the scene is switched after the build.
  sc.settings.kernel = kernel_from_name(kernel);
  Solver<2> solver(sc);
  const auto& g = sc.grid;
  const long nn = g.nodes();
  MaskCheck r;
  for (int step = 0; step < 300; ++step) {
    solver.step();
    solver.rigid_p2g();  // the bodies' presence at the next step (which recomputes it the same)
    std::vector<long> body_nodes;
    for (long i = 0; i < nn; ++i)
      for (int f = g.deformable; f < g.fields; ++f)
        if (g.rigid_presence(f, i) > 0) {
          body_nodes.push_back(i);
          break;
        }
    const std::vector<Vec<2>> moff_pass = g.moff;
    // the stand-alone P2G scatters every particle's offsets, in the same order; mass, momentum and
    // force come out the same, so the run goes on unchanged
    solver.reset_grid();
    solver.p2g(true);
    for (long i : body_nodes) {
      r.mismatches += g.moff[i][0] != moff_pass[i][0] || g.moff[i][1] != moff_pass[i][1];
      r.checked += g.mass[i] > 0;
    }
    if (step == 299)
      for (long i = 0; i < nn; ++i)
        if (g.mass[i] > 0) {
          ++r.with_mass;
          r.left_out += moff_pass[i].isZero(0.0) && !g.moff[i].isZero(0.0);
        }
  }
  return r;
}
}  // namespace

// uGIMP, and the quadratic B-spline, whose support (1.5 cells) reaches a node outside a rigid
// particle's current stencil after any move across a half-cell boundary: without the one-node
// growth of the moving bodies' marks the B-spline case fails. (With uGIMP a body meets a node
// outside its particles' stencils only after a move of more than 1/2 - a cells in one step, which
// the CFL condition keeps out of reach.)
TEST(OffsetMask, OffsetsAtRigidBodyNodesEqualAFullScatter) {
  for (const char* kernel : {"ugimp", "bspline2"}) {
    const MaskCheck r = check_mask(kernel);
    EXPECT_EQ(r.mismatches, 0) << kernel;
    EXPECT_GT(r.checked, 300 * 50) << kernel;  // the gate reads offsets at nodes with specimen mass
    EXPECT_GT(r.left_out, r.with_mass / 2) << kernel << ": the pass scattered offsets at " << r.with_mass - r.left_out
                                           << " of " << r.with_mass << " nodes";
  }
}
