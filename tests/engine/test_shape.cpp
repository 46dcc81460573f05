// Shape functions: partition of unity, zero gradient sum, linear field reproduction, and the
// uGIMP weight equal to the hat averaged over the particle domain.
#include <cmath>
#include <vector>

#include <gtest/gtest.h>

#include "grid/shape.hpp"

using namespace pbx;

namespace {
template <Kernel K>
void check_kernel(double a) {
  for (double s = 3.0; s < 5.0; s += 0.0137) {
    int base;
    std::array<double, 3> w, g;
    kernel_1d<K>(s, a, 1.0, base, w, g);
    double sw = 0, sg = 0, sx = 0, sxg = 0;
    for (int k = 0; k < 3; ++k) {
      sw += w[k];
      sg += g[k];
      sx += w[k] * (base + k);
      sxg += g[k] * (base + k);
      EXPECT_GE(w[k], -1e-15);
    }
    EXPECT_NEAR(sw, 1.0, 1e-13) << s;
    EXPECT_NEAR(sg, 0.0, 1e-13) << s;
    EXPECT_NEAR(sx, s, 1e-13) << s;    // linear completeness
    EXPECT_NEAR(sxg, 1.0, 1e-13) << s; // gradient of x is 1
  }
}
}  // namespace

TEST(Shape, LinearPartitionOfUnityAndCompleteness) { check_kernel<Kernel::linear>(0.25); }
TEST(Shape, UgimpPartitionOfUnityAndCompleteness) { check_kernel<Kernel::ugimp>(0.25); }
TEST(Shape, Bspline2PartitionOfUnityAndCompleteness) { check_kernel<Kernel::bspline2>(0.25); }

TEST(Shape, UgimpEqualsHatAveragedOverParticle) {
  const double a = 0.25;
  for (double s = 3.01; s < 4.0; s += 0.07) {
    int base;
    std::array<double, 3> w, g;
    kernel_1d<Kernel::ugimp>(s, a, 1.0, base, w, g);
    for (int k = 0; k < 3; ++k) {
      // midpoint rule over [s - a, s + a] of the hat centred at node base + k
      const int n = 20000;
      double avg = 0;
      for (int q = 0; q < n; ++q) {
        const double x = s - a + (q + 0.5) * 2 * a / n;
        avg += std::max(0.0, 1.0 - std::abs(x - (base + k)));
      }
      avg /= n;
      EXPECT_NEAR(w[k], avg, 1e-7) << "s=" << s << " k=" << k;
    }
  }
}

// The branch-free uGIMP stencil equals the piecewise definition (detail::ugimp_1d) node by node,
// for 1, 2 and 3 particles per cell, including positions on the piece boundaries.
TEST(Shape, UgimpStencilMatchesPiecewiseDefinition) {
  for (const double a : {0.5, 0.25, 1.0 / 6.0}) {
    std::vector<double> positions;
    for (double s = 3.0; s < 5.0; s += 0.00731) positions.push_back(s);
    for (double c = 3.0; c <= 5.0; c += 1.0)
      for (const double d : {0.0, a, -a, 0.5, -0.5, 1.0 - a, a - 1.0}) positions.push_back(c + d);
    for (const double s : positions) {
      int base;
      std::array<double, 3> w, g;
      kernel_1d<Kernel::ugimp>(s, a, 2.0, base, w, g);
      EXPECT_LE(std::abs(s - (base + 1)), 0.5 + 1e-15) << s;  // middle node nearest
      for (int k = 0; k < 3; ++k) {
        double wr, gr;
        detail::ugimp_1d(s - (base + k), a, 2.0, wr, gr);
        EXPECT_NEAR(w[k], wr, 1e-14) << "a=" << a << " s=" << s << " k=" << k;
        EXPECT_NEAR(g[k], gr, 1e-13) << "a=" << a << " s=" << s << " k=" << k;
      }
    }
  }
}

// The two-lane 2-D uGIMP stencil (make_stencil<2, ugimp>) gives the same bits as kernel_1d on each
// axis, including positions on and next to the piece boundaries and on node lines; the engine's
// results must not depend on which of the two computed a stencil.
TEST(Shape, TwoLaneUgimpStencilEqualsKernel1dBitForBit) {
  const Vec<2> origin(-1.0e-4, 2.0e-5);
  const double h = 5.0e-6, inv_h = 1.0 / h;
  for (const double a : {0.5, 0.25, 1.0 / 6.0}) {
    std::vector<double> cells;
    // negative cell coordinates too (the floor below zero) and far from the origin (the integer
    // conversion of the two-lane form)
    for (double s = -3.0; s < 4.0; s += 0.00731) cells.push_back(s);
    for (const double s : {12345.678, 99999.5, 250000.25, -4321.125}) cells.push_back(s);
    for (double c = -3.0; c <= 4.0; c += 1.0)
      for (const double d : {0.0, a, -a, 0.5, -0.5, 1.0 - a, a - 1.0})
        for (const double eps : {0.0, 1e-12, -1e-12}) cells.push_back(c + 0.5 + d + eps);
    for (std::size_t k = 0; k < cells.size(); ++k) {
      const Vec<2> x(origin[0] + cells[k] * h, origin[1] + cells[cells.size() - 1 - k] * h);
      const Stencil<2> st = make_stencil<2, Kernel::ugimp>(x, origin, inv_h, a);
      for (int d = 0; d < 2; ++d) {
        int base;
        std::array<double, 3> w, g;
        kernel_1d<Kernel::ugimp>((x[d] - origin[d]) * inv_h, a, inv_h, base, w, g);
        EXPECT_EQ(st.base[d], base) << "a=" << a << " x=" << x[d];
        for (int n = 0; n < 3; ++n) {
          EXPECT_EQ(st.w[d][n], w[n]) << "a=" << a << " x=" << x[d] << " node " << n;
          EXPECT_EQ(st.g[d][n], g[n]) << "a=" << a << " x=" << x[d] << " node " << n;
        }
      }
    }
  }
}
