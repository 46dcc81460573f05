// The fused USL pass scatters what the field contact reads (volume gradients, binder-layer sums,
// mass-centre offsets) only for particles whose stencils meet the nodes where two or more fields can
// be present (Solver::mark_contact_bases). At every node where two fields are present after the
// pass, those sums must equal a full P2G's to the bit; away from the contacts they must really be
// left out (else the test would not test the mask); and a particle that jumps a cell or more in one
// step, which the mask cannot foresee, must make the pass fall back to a full P2G.
#include <gtest/gtest.h>

#include <fstream>
#include <functional>
#include <sstream>

#include "../contact/two_disks_deck.hpp"
#include "contact/scatter_masks.hpp"
#include "setup/build_scene.hpp"
#include "io/deck_override.hpp"
#include "scene_fixture.hpp"

using namespace pbx;

namespace {

struct Sums {
  std::vector<Vec<2>> moff, vgrad, mref, mnorm;
  std::vector<Mat<2>> mdef;
  std::vector<double> mbond, minvt;
  explicit Sums(const Scene<2>& sc) : moff(sc.grid.moff), vgrad(sc.grid.vgrad) {
    const LayerSums<2>& l = sc.layer_data.sums;
    if (sc.layer_data.on()) mref = l.mref, mnorm = l.mnorm, mdef = l.mdef, mbond = l.mbond, minvt = l.minvt;
  }
  // every contact sum of node entry k equal to the bit
  bool same(const Sums& o, long k) const {
    const auto K = static_cast<std::size_t>(k);
    bool eq = moff[K] == o.moff[K] && vgrad[K] == o.vgrad[K];
    if (!mref.empty())
      eq = eq && mref[K] == o.mref[K] && mnorm[K] == o.mnorm[K] && mdef[K] == o.mdef[K] && mbond[K] == o.mbond[K] &&
           minvt[K] == o.minvt[K];
    return eq;
  }
};

struct MaskCheck {
  long mismatches = 0, contact_entries = 0, left_out = 0, with_mass = 0;
};

// Steps the scene; after each step compares the pass's sums with a full P2G's at every node entry
// of a field at a node where two or more fields have mass.
// `before` runs once the solver is made, before its first step.
MaskCheck check_mask(Scene<2>& sc, int steps, const std::function<void()>& before = {}) {
  Solver<2> solver(sc);
  if (before) before();
  const auto& g = sc.grid;
  const long nn = g.nodes();
  const int nf = g.deformable;
  MaskCheck r;
  for (int step = 0; step < steps; ++step) {
    solver.step();
    const Sums pass(sc);
    solver.reset_grid();
    solver.p2g(true);  // the stand-alone P2G, every particle, in the pass's order
    const Sums full(sc);
    for (long i = 0; i < nn; ++i) {
      int present = 0;
      for (int f = 0; f < nf; ++f) present += g.mass[g.at(f, i)] > 0.0;
      for (int f = 0; f < nf; ++f) {
        const long k = g.at(f, i);
        if (!(g.mass[k] > 0.0)) continue;
        if (present >= 2) {
          ++r.contact_entries;
          r.mismatches += !pass.same(full, k);
        }
        if (step == steps - 1) {
          ++r.with_mass;
          r.left_out += pass.vgrad[static_cast<std::size_t>(k)].isZero(0.0) &&
                        !full.vgrad[static_cast<std::size_t>(k)].isZero(0.0);
        }
      }
    }
  }
  return r;
}

std::string paper_deck(const std::string& cell) {
  std::ifstream in(std::string(PBXMPM_EXAMPLES_DIR) + "/paper/base.toml");
  std::stringstream ss;
  ss << in.rdbuf();
  return deck_with_overrides(ss.str(), "base.toml", {{"grid.cell_size", "\"" + cell + "\""}});
}

}  // namespace

// The paper specimen (ten grain fields and the binder, binder_layer between grains, Coulomb
// elsewhere, die and punch) at 10 um cells, over the first 100 steps.
TEST(ContactMask, ContactSumsOnThePaperSpecimenEqualAFullScatter) {
  Deck deck = Deck::from_string(paper_deck("10 um"), "base.toml", PBXMPM_EXAMPLES_DIR "/paper");
  Scene<2> sc = build_scene<2>(deck, SceneNotes::quiet);
  ASSERT_TRUE(sc.layer_data.on());
  const MaskCheck r = check_mask(sc, 100);
  EXPECT_EQ(r.mismatches, 0);
  EXPECT_GT(r.contact_entries, 100L * 5000);
  // node entries inside a grain, more than two nodes from another field: 17 % at 10 um cells
  EXPECT_GT(r.left_out, r.with_mass / 10) << "left out " << r.left_out << " of " << r.with_mass;
}

// Two disks 4.5 cells apart, the left one thrown at the right so fast (8 km/s, set after the
// solver chose its first time step from the deck's 20 m/s) that it crosses about four cells in the
// first step and overlaps the right one's nodes: the mask made before the step cannot foresee
// that, so the pass must redo the P2G in full.
TEST(ContactMask, AParticleJumpingACellFallsBackToAFullScatter) {
  std::string text = test::two_disks_deck("coulomb", "12 us", 60, "friction = 0.3\n");
  text.replace(text.find("center = [\"0.1 mm\""), 18, "center = [\"0.135 mm\"");
  Scene<2> sc = test::scene_from(text);
  const MaskCheck r = check_mask(sc, 1, [&] {
    for (std::size_t p = 0; p < sc.particles.size(); ++p)
      if (sc.particles.field[p] == 0) sc.particles.v[p] = Vec<2>(8000.0, 0.0);
  });
  EXPECT_EQ(r.mismatches, 0);
  EXPECT_GT(r.contact_entries, 0);
}

// A rank of a decomposed run sees complete masses only on its own node lines: marking with those
// bounds takes every node beyond them as a candidate, so it marks every base the unbounded
// marking does and more, never fewer (a particle left out must meet no node of two fields).
// Two fields 3 lines apart (x < 6 and x >= 9): no candidate anywhere; seen up to line 7, the
// nodes beyond are candidates, and so is line 7 (its 3 x 3 neighbourhood reaches line 8).
TEST(ContactMask, BoundedMarkingMarksAtLeastTheUnboundedBases) {
  Grid<2> g;
  g.n = {12, 6};
  g.h = 1.0;
  g.allocate(2);
  for (long y = 0; y < 6; ++y)
    for (long x = 0; x < 12; ++x) {
      if (x < 6) g.mass[static_cast<std::size_t>(g.at(0, x + 12 * y))] = 1.0;
      if (x >= 9) g.mass[static_cast<std::size_t>(g.at(1, x + 12 * y))] = 1.0;
    }
  ContactScatterMasks<2> all, bounded;
  all.mark_contact(g, 2, true);
  bounded.mark_contact(g, 2, true, 0, 7);
  ASSERT_NE(all.contact_bases(), nullptr);
  ASSERT_NE(bounded.contact_bases(), nullptr);
  for (long y = 0; y < 6; ++y)
    for (long x = 0; x < 12; ++x) {
      const long i = x + 12 * y;
      EXPECT_EQ(all.contact_bases()[i], 0) << x << "," << y;  // the fields never come within a node
      // a base reaches lines x .. x + 2: marked where that reaches line 7 or beyond
      EXPECT_EQ(bounded.contact_bases()[i] != 0, x + 2 >= 7) << x << "," << y;
    }
}
