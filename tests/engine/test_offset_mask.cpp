// The fused USL pass scatters the mass-centre offsets only for particles near a rigid body
// (Solver::mark_offset_bases): at every node where a body is present at the next step the sums
// must still equal those of a full P2G to the bit, and away from the bodies they must really be
// left out (else the test would not test the mask).
#include <gtest/gtest.h>

#include "block_deck.hpp"
#include "scene_fixture.hpp"

using namespace pbx;

TEST(OffsetMask, OffsetsAtRigidBodyNodesEqualAFullScatter) {
  // the die block 40 cells wide and 20 high, so most particles are far from the walls
  const std::string deck = test::block_deck(100, 0.01, "usl", "ugimp", 0.4, 0.2);
  Scene<2> sc = test::scene_from(deck);
  Solver<2> solver(sc);
  for (int s = 0; s < 300; ++s) solver.step();  // the punch has moved in and pushes the block
  solver.rigid_p2g();                           // the bodies' presence at the next step
  const auto& g = sc.grid;
  const long nn = g.nodes();
  std::vector<long> body_nodes;
  for (long i = 0; i < nn; ++i)
    for (int f = g.deformable; f < g.fields; ++f)
      if (g.rigid_presence(f, i) > 0) {
        body_nodes.push_back(i);
        break;
      }
  ASSERT_GT(body_nodes.size(), 100u);
  const std::vector<Vec<2>> moff_pass = g.moff;
  const std::vector<double> mass_pass = g.mass;
  solver.reset_grid();
  solver.p2g(true);  // the stand-alone P2G scatters every particle's offsets, in the same order
  long checked = 0;
  for (long i : body_nodes) {
    EXPECT_EQ(g.mass[i], mass_pass[i]) << "node " << i;
    EXPECT_EQ(g.moff[i][0], moff_pass[i][0]) << "node " << i;
    EXPECT_EQ(g.moff[i][1], moff_pass[i][1]) << "node " << i;
    checked += g.mass[i] > 0;
  }
  EXPECT_GT(checked, 50);  // the gate reads offsets at nodes with specimen mass
  long left_out = 0, with_mass = 0;
  for (long i = 0; i < nn; ++i)
    if (g.mass[i] > 0) {
      ++with_mass;
      left_out += moff_pass[i].isZero(0.0) && !g.moff[i].isZero(0.0);
    }
  EXPECT_GT(left_out, with_mass / 2) << "the pass scattered offsets at " << with_mass - left_out << " of " << with_mass << " nodes";
}
