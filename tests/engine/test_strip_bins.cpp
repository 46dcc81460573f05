// The strip bookkeeping of the race-free scatter (grid/strip_bins.hpp): the division-free home test
// agrees with strip_of_cell, and each parity phase hands out every strip of its parity exactly
// once, in an order whose consecutive strips are not neighbours of that parity; and, as domains
// (grid/domain.hpp), the strips own every node column once, a home particle's stencil stays within
// its strip's reach for every kernel, and two strips of one parity never reach the same node (the
// parity scheme's race freedom, which a width of 2 cells would break).
#include <gtest/gtest.h>

#include <cstdlib>
#include <random>
#include <set>
#include <vector>

#include "grid/shape.hpp"
#include "grid/strip_bins.hpp"

namespace pbx {

TEST(StripBins, HomeTestAgreesWithStripOfCell) {
  for (long cells : {3L, 7L, 64L, 200L, 401L, 1000L}) {
    StripBins b;
    b.setup(cells);
    for (long cx = -5; cx < cells + 5; ++cx)
      for (long s = 0; s < b.strips; ++s)
        EXPECT_EQ(b.in_strip(cx, s), b.strip_of_cell(cx) == s) << "cells " << cells << " cell " << cx << " strip " << s;
  }
}

TEST(StripBins, PhasesVisitEachStripOnceAndSpreadTheStart) {
  for (long cells : {3L, 9L, 12L, 27L, 30L, 33L, 200L, 401L, 1000L}) {
    StripBins b;
    b.setup(cells);
    std::multiset<long> seen;
    for (int phase = 0; phase < 2; ++phase) {
      for (long k = 0; k < b.phase_size(phase); ++k) {
        const long s = b.phase_strip(phase, k);
        ASSERT_GE(s, 0);
        ASSERT_LT(s, b.strips);
        EXPECT_EQ(s % 2, phase);
        seen.insert(s);
        // the strips handed out one after the other (run at the same time by two threads) are
        // more than one same-parity neighbour apart once a phase has five or more strips (with
        // four the order is 0, 4, 2, 6 in strip numbers)
        if (k > 0 && b.phase_size(phase) >= 5) {
          EXPECT_GT(std::abs(s - b.phase_strip(phase, k - 1)), 2) << cells << " " << k;
        }
      }
    }
    EXPECT_EQ(static_cast<long>(seen.size()), b.strips);
    for (long s = 0; s < b.strips; ++s) EXPECT_EQ(seen.count(s), 1u) << "strip " << s;
  }
}

// The scatter's visit order (visit_order): in one process each phase's strips in phase_strip's
// order and no lead part; with lead strips (a decomposed run's strips at its cuts) those come first
// in the part of their own parity, and every strip is still visited once, in its parity's phase.
TEST(StripBins, VisitOrderLeadsWithTheCutStripsAndVisitsEachOnce) {
  StripBins b;
  b.setup(120);  // 3-cell strips, 40 of them
  for (int phase = 0; phase < 2; ++phase) {
    EXPECT_TRUE(b.visit_order(2 * phase).empty());
    ASSERT_EQ(static_cast<long>(b.visit_order(2 * phase + 1).size()), b.phase_size(phase));
    for (long k = 0; k < b.phase_size(phase); ++k)
      EXPECT_EQ(b.visit_order(2 * phase + 1)[static_cast<std::size_t>(k)], b.phase_strip(phase, k));
  }
  b.lead_with({13, 26});  // a rank owning strips 13 ... 26
  EXPECT_EQ(b.visit_order(0), std::vector<long>{26});
  EXPECT_EQ(b.visit_order(2), std::vector<long>{13});
  std::multiset<long> seen;
  for (int part = 0; part < 4; ++part)
    for (const long s : b.visit_order(part)) {
      EXPECT_EQ(s % 2, part / 2) << "strip " << s << " in part " << part;
      seen.insert(s);
    }
  for (long s = 0; s < b.strips; ++s) EXPECT_EQ(seen.count(s), 1u) << "strip " << s;
}

namespace {
Grid<2> grid_of(long cells_x, long cells_y) {
  Grid<2> g;
  g.h = 1e-5;
  g.n = {cells_x + 1, cells_y + 1};
  g.allocate(1);
  return g;
}

template <Kernel K>
void stencils_stay_in_reach(const StripBins& b, const Grid<2>& g, std::mt19937& rng) {
  const double inv_h = 1.0 / g.h;
  const HalfWidth a(0.25);  // uGIMP at 2 x 2 particles per cell
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (long s = 0; s < b.strips; ++s) {
    const NodeBox<2> reach = b.domain<2>(g, s).reach(g);
    for (int k = 0; k < 400; ++k) {
      // a point of strip s where a particle may be (locate: 1 <= s < n - 2 cells on each axis)
      const double lo = std::max(1.0, static_cast<double>(s * b.width));
      const double hi = std::min(static_cast<double>(g.n[0]) - 2.0, static_cast<double>((s + 1) * b.width));
      if (!(hi > lo)) continue;
      const Vec<2> x(g.h * (lo + (hi - lo) * u(rng)), g.h * (1.0 + (static_cast<double>(g.n[1]) - 3.0) * u(rng)));
      ASSERT_EQ(b.locate<2>(g, inv_h, x, s), StripBins::kHome);
      const Stencil<2> st = make_stencil<2, K>(x, g.origin, inv_h, a);
      for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j)
          EXPECT_TRUE(reach.contains({st.base[0] + i, st.base[1] + j}))
              << "kernel " << static_cast<int>(K) << " strip " << s << " x " << x.transpose() / g.h;
    }
  }
}
}  // namespace

TEST(StripBins, StripsAsDomainsOwnEveryNodeOnceAndSameParityNeverShareANode) {
  std::mt19937 rng(7);
  for (long cells : {3L, 9L, 30L, 96L, 200L, 401L}) {
    const Grid<2> g = grid_of(cells, 12);
    StripBins b;
    b.setup(cells);
    long owned = 0;
    for (long s = 0; s < b.strips; ++s) {
      const Domain<2> ds = b.domain<2>(g, s);
      owned += ds.owned.count();
      for (long t = s + 1; t < b.strips; ++t) {
        const Domain<2> dt = b.domain<2>(g, t);
        EXPECT_FALSE(ds.owned.overlaps(dt.owned)) << cells << ": " << s << " " << t;
        // strips of one parity scatter at the same time: their reach must be disjoint; neighbours
        // do share ghost columns (else this check would hold for any width)
        if ((t - s) % 2 == 0) {
          EXPECT_FALSE(reach_overlaps(g, ds, dt)) << cells << ": " << s << " " << t;
        }
        if (t == s + 1) {
          EXPECT_TRUE(reach_overlaps(g, ds, dt)) << cells << ": " << s << " " << t;
        }
      }
    }
    EXPECT_EQ(owned, g.nodes()) << cells;
    stencils_stay_in_reach<Kernel::linear>(b, g, rng);
    stencils_stay_in_reach<Kernel::ugimp>(b, g, rng);
    stencils_stay_in_reach<Kernel::bspline2>(b, g, rng);
  }
  // strips two cells wide would let strips of one parity reach the same node column
  const Grid<2> g = grid_of(40, 4);
  StripBins narrow;
  narrow.setup(40);
  narrow.width = 2;
  narrow.strips = 20;
  EXPECT_TRUE(reach_overlaps(g, narrow.domain<2>(g, 0), narrow.domain<2>(g, 2)));
}

}  // namespace pbx
