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
    EXPECT_NEAR(sx, s, 1e-13) << s;     // linear completeness
    EXPECT_NEAR(sxg, 1.0, 1e-13) << s;  // gradient of x is 1
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

// The checks above leave one weight and one gradient free per point on a 3-node stencil (three
// conditions, three nodes: a wrong B-spline or a wrong gradient with the right sums would pass).
// Here each weight is compared with the kernel's closed form evaluated independently at the node's
// distance, and each gradient with a central difference of the weights, for all three kernels, at
// a cell size h = 0.5 (inv_h = 2, so a gradient missing its 1/h fails too).
namespace {
// Closed forms of docs/theory/engine.md, from the node's distance xi in cells.
double hat(double xi) { return std::max(0.0, 1.0 - std::abs(xi)); }
double bspline2(double xi) {
  const double r = std::abs(xi);
  return r <= 0.5 ? 0.75 - r * r : (r <= 1.5 ? 0.5 * (1.5 - r) * (1.5 - r) : 0.0);
}
double ugimp(double xi, double a) {
  const double r = std::abs(xi);
  if (r < a) return 1.0 - (xi * xi + a * a) / (2 * a);
  if (r < 1 - a) return 1.0 - r;
  if (r < 1 + a) return (1 + a - r) * (1 + a - r) / (4 * a);
  return 0.0;
}

template <Kernel K>
double closed_form(double xi, double a) {
  if constexpr (K == Kernel::linear)
    return hat(xi);
  else if constexpr (K == Kernel::ugimp)
    return ugimp(xi, a);
  else
    return bspline2(xi);
}

// Positions where a kernel's weight has a kink (its gradient jumps): a difference straddling one
// is skipped. Kinks sit at xi = 0, +-1 (linear), +-a, +-(1 -+ a) (uGIMP) and are absent for the
// other kernels' gradients (B-spline and uGIMP are C1, but linear is C0 at nodes).
bool near_kink(double s, double a, double d) {
  const double u = s - std::floor(s);  // position within the cell
  for (const double k : {0.0, 1.0, a, 1.0 - a})
    if (std::abs(u - k) < 2 * d) return true;
  return false;
}

template <Kernel K>
void check_against_closed_form(double a) {
  const double inv_h = 2.0, d = 1e-6;  // d in cells
  int checked = 0;
  for (double s = 3.0; s < 5.0; s += 0.00917) {
    int base;
    std::array<double, 3> w, g;
    kernel_1d<K>(s, a, inv_h, base, w, g);
    for (int k = 0; k < 3; ++k) {
      const double xi = s - (base + k);
      EXPECT_NEAR(w[k], closed_form<K>(xi, a), 1e-14) << "s=" << s << " node " << k;
      if (near_kink(s, a, d)) continue;
      // dS/dx = dS/ds * inv_h, with s in cells
      const double fd = (closed_form<K>(xi + d, a) - closed_form<K>(xi - d, a)) / (2 * d) * inv_h;
      EXPECT_NEAR(g[k], fd, 1e-7 * inv_h) << "s=" << s << " node " << k;
      ++checked;
    }
    // every node the kernel reaches is in the stencil: the weights cover the whole kernel
    for (const int outside : {base - 1, base + 3}) EXPECT_EQ(closed_form<K>(s - outside, a), 0.0) << s;
  }
  EXPECT_GT(checked, 500);
}
}  // namespace

TEST(Shape, LinearWeightsAndGradientsEqualTheClosedForm) { check_against_closed_form<Kernel::linear>(0.25); }
TEST(Shape, UgimpWeightsAndGradientsEqualTheClosedForm) {
  for (const double a : {0.25, 0.5, 1.0 / 6.0}) check_against_closed_form<Kernel::ugimp>(a);
}
TEST(Shape, Bspline2WeightsAndGradientsEqualTheClosedForm) { check_against_closed_form<Kernel::bspline2>(0.25); }

// The quadratic B-spline's second moment about the particle is 1/4 cell^2 wherever the particle
// is (a property of the uniform B-spline, independent of the checks above).
TEST(Shape, Bspline2SecondMomentIsAQuarterCellSquared) {
  for (double s = 3.0; s < 5.0; s += 0.0137) {
    int base;
    std::array<double, 3> w, g;
    kernel_1d<Kernel::bspline2>(s, 0.25, 1.0, base, w, g);
    double m2 = 0;
    for (int k = 0; k < 3; ++k) m2 += w[k] * (base + k - s) * (base + k - s);
    EXPECT_NEAR(m2, 0.25, 1e-14) << s;
  }
}

// The 2-D tensor product: for_each_node's S and gradS against the product of the closed forms and
// its central difference in x and y, for each kernel (a transposed factor, or a gradient taken
// from the wrong axis, fails here and nowhere above).
namespace {
template <Kernel K>
void check_tensor_product() {
  const double h = 0.5, inv_h = 1 / h, a = 0.25, d = 1e-6;
  const Vec<2> origin(-1.0, 0.5);
  const std::array<long, 2> stride{1, 100};
  for (const Vec<2>& x : {Vec<2>(0.3170, 1.8125), Vec<2>(1.0441, 2.3390), Vec<2>(-0.2083, 0.9051)}) {
    const Stencil<2> st = make_stencil<2, K>(x, origin, inv_h, a);
    int visited = 0;
    double sum = 0;
    for_each_node<2>(st, stride, [&](long node, double S, const Vec<2>& G) {
      const long i = node % stride[1], j = node / stride[1];
      const double xi = (x[0] - origin[0]) * inv_h - i, eta = (x[1] - origin[1]) * inv_h - j;
      const auto w = [&](double u, double v) { return closed_form<K>(u, a) * closed_form<K>(v, a); };
      EXPECT_NEAR(S, w(xi, eta), 1e-14) << node;
      EXPECT_NEAR(G[0], (w(xi + d, eta) - w(xi - d, eta)) / (2 * d) * inv_h, 1e-7) << node;
      EXPECT_NEAR(G[1], (w(xi, eta + d) - w(xi, eta - d)) / (2 * d) * inv_h, 1e-7) << node;
      ++visited;
      sum += S;
    });
    EXPECT_EQ(visited, 9);
    EXPECT_NEAR(sum, 1.0, 1e-14);
  }
}
}  // namespace

TEST(Shape, TensorProductWeightsAndGradientsIn2D) {
  check_tensor_product<Kernel::linear>();
  check_tensor_product<Kernel::ugimp>();
  check_tensor_product<Kernel::bspline2>();
}

// The bspline2 basis clamped at fixed node lines lo and hi (the die's walls): inside [lo, hi] a
// partition of unity that reproduces linear fields (value and gradient), only node lo (hi) nonzero
// on the line itself (what makes a wall constraint at that node hold the particles on it), equal to
// the open-knot closed form (the hat between lo and lo + 1 within half a cell of lo), the standard
// B-spline from one and a half cells in, continuous with a continuous gradient where the two pieces
// meet, and coordinates beyond a line taken onto it. The unclamped B-spline gives 1/8 at the line
// to the node beyond it and fails each of the first three checks.
TEST(Shape, Bspline2ClampedAtFixedNodeLines) {
  const int lo = 3, hi = 9;
  const double inv_h = 2.0;  // h = 0.5
  auto at = [&](double s, int node, bool grad) {
    int base;
    std::array<double, 3> w, g;
    bspline2_clamped_1d(s, lo, hi, inv_h, base, w, g);
    const int k = node - base;
    return k < 0 || k > 2 ? 0.0 : (grad ? g[static_cast<std::size_t>(k)] : w[static_cast<std::size_t>(k)]);
  };
  for (double s = lo; s <= hi + 1e-12; s += 0.00913) {
    int base;
    std::array<double, 3> w, g;
    bspline2_clamped_1d(s, lo, hi, inv_h, base, w, g);
    double sw = 0, sg = 0, sx = 0, sxg = 0;
    for (int k = 0; k < 3; ++k) {
      const int node = base + k;
      if (node < lo || node > hi) {
        EXPECT_EQ(w[static_cast<std::size_t>(k)], 0.0) << "s=" << s << " node " << node << " lies beyond a line";
        EXPECT_EQ(g[static_cast<std::size_t>(k)], 0.0) << "s=" << s;
      }
      EXPECT_GE(w[static_cast<std::size_t>(k)], -1e-15) << s;
      sw += w[static_cast<std::size_t>(k)];
      sg += g[static_cast<std::size_t>(k)];
      sx += w[static_cast<std::size_t>(k)] * node;
      sxg += g[static_cast<std::size_t>(k)] * node / inv_h;
    }
    EXPECT_NEAR(sw, 1.0, 1e-13) << s;
    EXPECT_NEAR(sg, 0.0, 1e-12) << s;
    EXPECT_NEAR(sx, s, 1e-13) << s;
    EXPECT_NEAR(sxg, 1.0, 1e-13) << s;
    // the open-knot closed form near the lines, the standard B-spline away from them
    if (s < lo + 0.5) {
      EXPECT_NEAR(at(s, lo, false), 1.0 - (s - lo), 1e-14) << s;
      EXPECT_NEAR(at(s, lo + 1, false), s - lo, 1e-14) << s;
    } else if (s > hi - 0.5) {
      EXPECT_NEAR(at(s, hi, false), 1.0 - (hi - s), 1e-14) << s;
    } else if (s >= lo + 1.5 && s <= hi - 1.5) {
      int b2;
      std::array<double, 3> w2, g2;
      kernel_1d<Kernel::bspline2>(s, 0.25, inv_h, b2, w2, g2);
      EXPECT_EQ(b2, base);
      for (int k = 0; k < 3; ++k) EXPECT_EQ(w[static_cast<std::size_t>(k)], w2[static_cast<std::size_t>(k)]) << s;
    }
  }
  // on the lines: only the line's own node
  EXPECT_DOUBLE_EQ(at(lo, lo, false), 1.0);
  EXPECT_DOUBLE_EQ(at(lo, lo + 1, false), 0.0);
  EXPECT_DOUBLE_EQ(at(hi, hi, false), 1.0);
  EXPECT_DOUBLE_EQ(at(hi, hi - 1, false), 0.0);
  // C1 where the pieces meet (half a cell from a line) and across the standard pieces' joints
  for (const double s0 : {lo + 0.5, lo + 1.5, hi - 0.5, hi - 1.5})
    for (int node = lo; node <= lo + 3; ++node)
      for (const int n2 : {node, hi - (node - lo)})
        for (const bool grad : {false, true})
          EXPECT_NEAR(at(s0 - 1e-9, n2, grad), at(s0 + 1e-9, n2, grad), 1e-7)
              << "s=" << s0 << " node " << n2 << (grad ? " gradient" : " weight");
  // beyond a line: the weights of the line
  EXPECT_DOUBLE_EQ(at(lo - 0.3, lo, false), 1.0);
  EXPECT_DOUBLE_EQ(at(hi + 0.7, hi, false), 1.0);
}
