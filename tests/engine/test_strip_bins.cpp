// The strip bookkeeping of the race-free scatter (grid/strip_bins.hpp): the division-free home test
// agrees with strip_of_cell, and each parity phase hands out every strip of its parity exactly
// once, in an order whose consecutive strips are not neighbours of that parity.
#include <gtest/gtest.h>

#include <cstdlib>
#include <set>

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

}  // namespace pbx
