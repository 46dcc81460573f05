#pragma once
// Shape functions S_ip and gradients G_ip = dS_ip/dx_p, as tensor products of 1-D kernels.
// Every kernel touches at most 3 nodes per axis, so one Stencil type serves all of them.
// Formulas (h = cell size, xi = (x_p - x_i)/h, a = l_p/h the particle half-width in cells):
//  linear:   S = 1 - |xi|
//  uGIMP:    |xi| < a: 1 - (xi^2 + a^2)/(2a);  a <= |xi| < 1-a: 1 - |xi|;
//            1-a <= |xi| < 1+a: (1 + a - |xi|)^2/(4a)   (Bardenhagen & Kober 2004)
//  bspline2: |xi| <= 1/2: 3/4 - xi^2;  1/2 <= |xi| <= 3/2: (3/2 - |xi|)^2/2  (Steffen et al. 2008)
//            clamped at a fixed boundary node line L (ClampedNodes): within half a cell of L the
//            basis is the hat between L and L + 1, i.e. S'_L = S_L + 2 S_(L-1), S'_(L+1) = S_(L+1) - S_(L-1)
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <string>
#include <type_traits>

#include <emmintrin.h>

#include "core/tensor.hpp"

namespace pbx {

enum class Kernel { linear, ugimp, bspline2 };

Kernel kernel_from_name(const std::string& name);  // throws InputError
std::string kernel_name(Kernel k);

// Calls f with kernel k as a compile-time constant (std::integral_constant<Kernel, k>): one switch
// per stage, not per particle.
template <class F>
void with_kernel(Kernel k, F&& f) {
  switch (k) {
    case Kernel::linear:
      f(std::integral_constant<Kernel, Kernel::linear>{});
      break;
    case Kernel::ugimp:
      f(std::integral_constant<Kernel, Kernel::ugimp>{});
      break;
    case Kernel::bspline2:
      f(std::integral_constant<Kernel, Kernel::bspline2>{});
      break;
  }
}

// A particle's half-width a in cells (uGIMP) with the reciprocals the kernel uses. A stage builds
// it once, so the two divisions are not repeated per particle (the compiler does not hoist them
// out of a particle loop that might not run: they could trap). Implicit from a double.
struct HalfWidth {
  double a, inv_2a, inv_4a;
  HalfWidth(double half_width) : a(half_width), inv_2a(0.5 / half_width), inv_4a(0.25 / half_width) {}  // NOLINT
};

template <int D>
struct Stencil {
  std::array<int, D> base;                 // lowest node index per axis
  std::array<std::array<double, 3>, D> w;  // weights of nodes base..base+2
  std::array<std::array<double, 3>, D> g;  // d w / d x_p (1/m)
};

namespace detail {

inline void ugimp_1d(double xi, double a, double inv_h, double& w, double& g) {
  const double r = std::abs(xi), sgn = xi < 0 ? -1.0 : 1.0;
  if (r < a) {
    w = 1.0 - (xi * xi + a * a) / (2.0 * a);
    g = -xi / a * inv_h;
  } else if (r < 1.0 - a) {
    w = 1.0 - r;
    g = -sgn * inv_h;
  } else if (r < 1.0 + a) {
    const double q = 1.0 + a - r;
    w = q * q / (4.0 * a);
    g = -sgn * q / (2.0 * a) * inv_h;
  } else {
    w = 0.0;
    g = 0.0;
  }
}

}  // namespace detail

// s: particle coordinate in cell units relative to the grid origin; a: half-width in cells.
template <Kernel K>
inline void kernel_1d(double s, double a, double inv_h, int& base, std::array<double, 3>& w, std::array<double, 3>& g) {
  if constexpr (K == Kernel::linear) {
    const double fl = std::floor(s);
    base = static_cast<int>(fl);
    const double f = s - fl;
    w = {1.0 - f, f, 0.0};
    g = {-inv_h, inv_h, 0.0};
  } else if constexpr (K == Kernel::ugimp) {
    // With the middle node nearest to the particle, u = xi of the middle node lies in [-1/2, 1/2)
    // and a <= 1/2, so each node meets at most two pieces of the kernel: the middle node the
    // quadratic cap or the hat, the outer nodes (|xi| = 1 -+ u) the hat, the quadratic tail or
    // nothing. Written as selects, the compiler emits no branches (the pieces switch at random
    // as particles move, so branches would mispredict).
    const double fl = std::floor(s + 0.5);
    base = static_cast<int>(fl) - 1;
    const double u = s - fl;
    const double inv_2a = 0.5 / a, inv_4a = 0.25 / a, r = std::abs(u);
    const double sgn = u < 0 ? -1.0 : 1.0;
    w[1] = r < a ? 1.0 - (u * u + a * a) * inv_2a : 1.0 - r;
    g[1] = (r < a ? -u * (2.0 * inv_2a) : -sgn) * inv_h;
    // node base (xi = 1 + u >= 1/2): hat while u < -a, tail while u < a
    const double q0 = a - u, q2 = a + u;
    w[0] = u < -a ? -u : (u < a ? q0 * q0 * inv_4a : 0.0);
    g[0] = (u < -a ? -1.0 : (u < a ? -q0 * inv_2a : 0.0)) * inv_h;
    // node base+2 (xi = u - 1 <= -1/2): mirror image
    w[2] = u > a ? u : (u > -a ? q2 * q2 * inv_4a : 0.0);
    g[2] = (u > a ? 1.0 : (u > -a ? q2 * inv_2a : 0.0)) * inv_h;
  } else {
    const double fl = std::floor(s + 0.5);
    base = static_cast<int>(fl) - 1;
    const double u = s - fl;  // in [-1/2, 1/2): distance to the middle node
    // nodes base (xi = u + 1), base+1 (xi = u), base+2 (xi = u - 1)
    const double q0 = 0.5 - u, q2 = 0.5 + u;
    w = {0.5 * q0 * q0, 0.75 - u * u, 0.5 * q2 * q2};
    g = {-q0 * inv_h, -2.0 * u * inv_h, q2 * inv_h};
  }
}

// Node lines where the bspline2 basis is clamped: fixed boundaries the material stays on one side
// of (the die's walls and floor). Beside such a line the standard B-spline of the node beyond it
// still carries weight (1/8 at the line), so a node one cell inside feels a net force under a
// uniform stress and the wall takes too little of it: in the die column the wall/punch ratio came
// out 7 % low (4 cells wide) and the confined modulus 1.4 % low (10 um cells). Folding the outer
// node's function into the two inner ones (S'_L = S_L + 2 S_(L-1), S'_(L+1) = S_(L+1) - S_(L-1))
// keeps the partition of unity, reproduces linear fields, is C1 at half a cell from the line and
// leaves only S'_L nonzero on it: the hat between L and L + 1 there (the open-knot quadratic
// B-spline). Coordinates beyond a line are clamped onto it. docs/theory/engine.md.
template <int D>
struct ClampedNodes {
  static constexpr int kNone = std::numeric_limits<int>::max() / 4;
  std::array<int, D> lo, hi;  // node index per axis: the material lies in [lo, hi]; -kNone / kNone: no line
  ClampedNodes() {
    lo.fill(-kNone);
    hi.fill(kNone);
  }
};

// kernel_1d<bspline2> with the basis clamped at node lines lo and hi (s in cells from the origin).
inline void bspline2_clamped_1d(double s, int lo, int hi, double inv_h, int& base, std::array<double, 3>& w,
                                std::array<double, 3>& g) {
  s = std::min(std::max(s, static_cast<double>(lo)), static_cast<double>(hi));
  kernel_1d<Kernel::bspline2>(s, 0.0, inv_h, base, w, g);
  if (base == lo - 1) {  // node base lies beyond lo
    w[1] += 2.0 * w[0];
    w[2] -= w[0];
    g[1] += 2.0 * g[0];
    g[2] -= g[0];
    w[0] = g[0] = 0.0;
  }
  if (base + 2 == hi + 1) {  // node base + 2 lies beyond hi
    w[1] += 2.0 * w[2];
    w[0] -= w[2];
    g[1] += 2.0 * g[2];
    g[0] -= g[2];
    w[2] = g[2] = 0.0;
  }
}

// clamp: the grid's clamped node lines, for a material particle (nullptr: none; rigid particles lie
// beyond them). Only bspline2 reads it: a uGIMP particle's support ends at its own edge.
template <int D, Kernel K>
inline Stencil<D> make_stencil(const Vec<D>& x, const Vec<D>& origin, double inv_h, const HalfWidth& a,
                               const ClampedNodes<D>* clamp = nullptr) {
  Stencil<D> st;
  for (int d = 0; d < D; ++d) {
    const double s = (x[d] - origin[d]) * inv_h;
    if constexpr (K == Kernel::bspline2) {
      if (clamp) {
        bspline2_clamped_1d(s, clamp->lo[d], clamp->hi[d], inv_h, st.base[d], st.w[d], st.g[d]);
        continue;
      }
    }
    kernel_1d<K>(s, a.a, inv_h, st.base[d], st.w[d], st.g[d]);
  }
  return st;
}

namespace detail {
using v2d = double __attribute__((vector_size(16)));
using v2l = long long __attribute__((vector_size(16)));
inline v2d splat(double x) { return v2d{x, x}; }
}  // namespace detail

// 2-D uGIMP, both axes at once in one two-lane vector, with the selects of kernel_1d<ugimp> as
// lane masks. The compiler turns the scalar selects into branches, and with two particles per
// cell every particle sits on a piece boundary of the kernel (|u| = a) at the start and drifts
// to either side: the branches mispredict at random, twice per particle and step. The lanes do
// the same IEEE operations as kernel_1d, so the stencil is the same bit for bit (tested).
template <>
inline Stencil<2> make_stencil<2, Kernel::ugimp>(const Vec<2>& x, const Vec<2>& origin, double inv_h,
                                                 const HalfWidth& hw, const ClampedNodes<2>*) {
  using detail::splat;
  using detail::v2d;
  using detail::v2l;
  const v2d s = {(x[0] - origin[0]) * inv_h, (x[1] - origin[1]) * inv_h};
  const v2d sh = s + splat(0.5);
  // Truncation through packed 32-bit integers (SSE2 cvttpd2dq/cvtdq2pd): SSE2 has no packed
  // conversion to 64-bit integers, and the one through v2l was four scalar conversions per
  // stencil. Coordinates in cells are far below 2^31.
  __m128i ti = _mm_cvttpd_epi32(sh);
  v2d fl = _mm_cvtepi32_pd(ti);
  const v2l below = fl > sh;  // floor below zero: one less
  fl = below ? fl - splat(1.0) : fl;
  ti = _mm_add_epi32(ti, _mm_shuffle_epi32(reinterpret_cast<__m128i>(below), _MM_SHUFFLE(2, 0, 2, 0)));
  const v2d u = s - fl;
  const v2d inv_2a = splat(hw.inv_2a), inv_4a = splat(hw.inv_4a), va = splat(hw.a), ma = splat(-hw.a);
  const v2d one = splat(1.0), zero = splat(0.0), ih = splat(inv_h);
  const v2d r = u < zero ? -u : u;
  const v2d sgn = u < zero ? -one : one;
  const v2d w1 = r < va ? one - (u * u + va * va) * inv_2a : one - r;
  const v2d g1 = (r < va ? -u * (splat(2.0) * inv_2a) : -sgn) * ih;
  const v2d q0 = va - u, q2 = va + u;
  const v2d w0 = u < ma ? -u : (u < va ? q0 * q0 * inv_4a : zero);
  const v2d g0 = (u < ma ? -one : (u < va ? -q0 * inv_2a : zero)) * ih;
  const v2d w2 = u > va ? u : (u > ma ? q2 * q2 * inv_4a : zero);
  const v2d g2 = (u > va ? one : (u > ma ? q2 * inv_2a : zero)) * ih;
  Stencil<2> st;
  st.base[0] = _mm_cvtsi128_si32(ti) - 1;
  st.base[1] = _mm_cvtsi128_si32(_mm_srli_si128(ti, 4)) - 1;
  for (int d = 0; d < 2; ++d) {
    st.w[d] = {w0[d], w1[d], w2[d]};
    st.g[d] = {g0[d], g1[d], g2[d]};
  }
  return st;
}

// Calls f(node_offset_index, S, gradS) for the 3^D nodes of a stencil. `stride` gives the node
// index step per axis; nodes with zero weight are visited too (branch-free inner loop).
template <int D, class Fn>
inline void for_each_node(const Stencil<D>& st, const std::array<long, D>& stride, Fn&& f) {
  if constexpr (D == 2) {
    const long b0 = st.base[0] * stride[0] + st.base[1] * stride[1];
    for (int j = 0; j < 3; ++j)
      for (int i = 0; i < 3; ++i) {
        const double S = st.w[0][i] * st.w[1][j];
        Vec<2> G(st.g[0][i] * st.w[1][j], st.w[0][i] * st.g[1][j]);
        f(b0 + i + j * stride[1], S, G);
      }
  } else {
    const long b0 = st.base[0] * stride[0] + st.base[1] * stride[1] + st.base[2] * stride[2];
    for (int k = 0; k < 3; ++k)
      for (int j = 0; j < 3; ++j)
        for (int i = 0; i < 3; ++i) {
          const double S = st.w[0][i] * st.w[1][j] * st.w[2][k];
          Vec<3> G(st.g[0][i] * st.w[1][j] * st.w[2][k], st.w[0][i] * st.g[1][j] * st.w[2][k],
                   st.w[0][i] * st.w[1][j] * st.g[2][k]);
          f(b0 + i + j * stride[1] + k * stride[2], S, G);
        }
  }
}

}  // namespace pbx
