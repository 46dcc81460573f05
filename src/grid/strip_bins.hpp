#pragma once
// The grid's strips: its node columns split into vertical strips of `width` >= 3 cells, each the
// home of the particles stored in one storage range: a Domain (grid/domain.hpp) owning the strip's
// node columns, whose ghost layers are the columns its particles' stencils reach beyond it.
// They give a race-free, deterministic parallel scatter. A
// particle's 3x3 stencil reaches one node column beyond its strip on each side, so strips of the
// same parity never touch the same node: even strips scatter in parallel, then odd strips.
//
// Particles are stored strip by strip (order_by_strip, solver/scene.hpp), so a strip's particles
// are the storage range [begin[s], begin[s+1]): its home strip, fixed for the run. A particle that
// has moved out of its home strip (a stray; rare: strains are small) would break the parity
// argument, so it is left out of the two phases and scattered afterwards, serially, in index
// order. The sum order at every node is then fixed by storage order and positions alone, so
// results are bit-identical for any thread count. Strip width does not depend on threads.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

#include "core/parallel.hpp"
#include "grid/domain.hpp"
#include "grid/grid.hpp"

namespace pbx {

struct StripBins {
  long width = 3;  // cells per strip
  long strips = 0;
  std::vector<long> begin;            // home range of strip s: [begin[s], begin[s + 1])
  std::vector<std::uint8_t> stray;    // per particle: outside its home strip
  std::vector<std::uint32_t> strays;  // the strays, ascending
  // The strips whose parts of a sum this process makes: all of them, or a decomposed run's rank's
  // own, with the gather of the other ranks' parts (fold below).
  long own_lo = 0, own_hi = 0;
  PartGather* gather = nullptr;
  DeferredSums* deferred = nullptr;  // where fold_then's sums wait (null: booked at once)
  // The strips whose nodes this process's node stages visit: all of them, or a rank's own and the
  // two beyond each cut, where its particles' stencils, its strays' and the stray zones reach (its
  // particles put no mass on other nodes).
  long visit_lo = 0, visit_hi = 0;

  void setup(long cells_x) {
    width = std::max(3L, cells_x / 32);
    strips = std::max(1L, (cells_x + width - 1) / width);
    own_lo = visit_lo = 0;
    own_hi = visit_hi = strips;
    lead_with({});
  }
  // The strips of a grid (its cells along x), all of them this process's.
  template <int D>
  static StripBins of_grid(const Grid<D>& g) {
    StripBins b;
    b.setup(g.n[0] - 1);
    return b;
  }

  // A sum over the grid's nodes or the particles, strip by strip: body(s, part) accumulates strip
  // s into its part, in storage order, and the parts are summed in strip order (core/parallel.hpp).
  // The strips [visit_lo, visit_hi) are visited, beyond a rank's own too (a node stage must act on
  // the node lines its particles reach beyond its strips; another rank's strips hold none of its
  // particles), but only this rank's parts enter the sum, with the other ranks' gathered: the
  // bits of the one-process sum on any thread and rank count. Strip-major, so that a rank's parts are whole
  // parts: the node sums were made over 1,024-node blocks in node order before 2026-12-07, which
  // cut across the strips (x runs fastest in node order).
  template <class T, class Body>
  T fold(const T& zero, Body&& body) const {
    std::vector<T> own = own_parts(zero, body);
    return sum_parts(own, zero, gather);
  }
  // The same sum for the run's books (nothing in the step reads it), handed to book(sum): at once,
  // or where the strips defer their sums (`deferred`, a decomposed run), at its next settle, in the
  // order the sums were made (core/parallel.hpp, DeferredSums).
  template <class T, class Body, class Book>
  void fold_then(const T& zero, Body&& body, Book&& book) const {
    std::vector<T> own = own_parts(zero, body);
    if (!deferred || !deferred->defers()) {
      book(sum_parts(own, zero, gather));
      return;
    }
    deferred->add(flatten_parts(own),
                  [zero, book](const std::vector<double>& all) { book(sum_flat_parts(all, zero)); });
  }
  // Strip s's nodes in node order, as runs f(begin, end) of consecutive node indices: its node
  // columns (the outer strips to the grid's edges) on every row (every node along the other axes).
  template <int D, class F>
  void for_each_node_run(const Grid<D>& g, long s, F&& f) const {
    const long nx = g.n[0];
    const long c0 = s == 0 ? 0 : s * width, c1 = s == strips - 1 ? nx : std::min(nx, (s + 1) * width);
    const long rows = g.nodes() / nx;
    for (long r = 0; r < rows; ++r) f(r * nx + c0, r * nx + c1);
  }
  // The parity phases of a parallel scatter: phase 0 takes the even strips, phase 1 the odd ones.
  long phase_size(int phase) const { return (strips - phase + 1) / 2; }
  // The k-th strip a phase hands out: the first and second halves of the phase's strips
  // alternate (0, h, 1, h+1, ... in units of two strips), so the strips that threads run at the
  // same time lie far apart. Neighbours of one parity are only four node columns apart, and two
  // threads scattering them row by row at the same pace shared the cache lines between them
  // (the scatter cost 40 % more cycles with two threads than with one). The visit order does not
  // change any nodal sum: strips of one parity never touch the same node.
  long phase_strip(int phase, long k) const {
    const long half = (phase_size(phase) + 1) / 2;
    return phase + 2 * (k % 2 == 0 ? k / 2 : half + k / 2);
  }
  // The order a scatter visits its strips, in four parts: k = 2 x phase + 0, the phase's strips at
  // a decomposed run's cuts (`lead`), whose node lines the neighbouring rank needs, so they leave as
  // soon as they are made and travel while the rest of the phase runs; k = 2 x phase + 1, the
  // phase's other strips in phase_strip's order (in one process, all of them). Strips of one phase
  // touch no common node, so the order changes no sum.
  const std::vector<long>& visit_order(int k) const { return order_[static_cast<std::size_t>(k)]; }
  void lead_with(const std::vector<long>& lead) {
    for (auto& o : order_) o.clear();
    for (int phase = 0; phase < 2; ++phase)
      for (long k = 0; k < phase_size(phase); ++k) {
        const long s = phase_strip(phase, k);
        const bool leads = std::find(lead.begin(), lead.end(), s) != lead.end();
        order_[static_cast<std::size_t>(2 * phase + (leads ? 0 : 1))].push_back(s);
      }
  }
  // Strip s as a domain: its cells' node columns (the outer strips to the grid's edges), every node
  // along the other axes. Two strips of one parity have disjoint reach when width >= 3 (test).
  template <int D>
  Domain<D> domain(const Grid<D>& g, long s) const {
    Domain<D> dom;
    for (int d = 0; d < D; ++d) dom.owned.lo[d] = 0, dom.owned.hi[d] = g.n[d];
    if (s > 0) dom.owned.lo[0] = s * width;
    if (s < strips - 1) dom.owned.hi[0] = (s + 1) * width;
    return dom;
  }
  // strip_of_cell(cell_x) == s, without the division (the outer strips take every cell beyond)
  bool in_strip(long cell_x, long s) const {
    return (s == 0 || cell_x >= s * width) && (s == strips - 1 || cell_x < (s + 1) * width);
  }
  long strip_of_cell(long cell_x) const { return std::min(strips - 1, std::max(0L, cell_x / width)); }
  // s: x-coordinate in cell units from the grid origin
  long strip_of(double s) const { return strip_of_cell(static_cast<long>(std::floor(s))); }
  // Where a particle of home strip `home`, now at x, is: kHome, kStray (inside the grid, in another
  // strip) or kOutside (its stencil would leave the grid: the run must stop before it scatters).
  enum Place { kHome = 0, kStray = 1, kOutside = 2 };
  template <int D>
  Place locate(const Grid<D>& g, double inv_h, const Vec<D>& x, long home) const {
    Place r = kHome;
    for (int d = 0; d < D; ++d) {
      const double s = (x[d] - g.origin[d]) * inv_h;
      if (!(s >= 1.0 && s < static_cast<double>(g.n[d]) - 2.0)) return kOutside;
      // s >= 1 here, so truncation is the floor (std::floor is a library call on baseline x86-64);
      // the home test compares with the strip's cell range instead of dividing (a 64-bit idiv
      // per particle and step was 3-5 % of the fused pass)
      if (d == 0 && !in_strip(static_cast<long>(s), home)) r = kStray;
    }
    return r;
  }
  // After particle p (home strip `home`) moved to x: its stray flag set, `strays` counted up, and
  // `left` lowered to p when its stencil would leave the grid. The tallies are the caller's (OpenMP
  // reduction variables); collect_strays(strays) rebuilds the list after the pass.
  template <int D>
  Place relocate(const Grid<D>& g, double inv_h, const Vec<D>& x, long home, std::uint32_t p, std::uint32_t& left,
                 long& strays_counted) {
    const Place where = locate<D>(g, inv_h, x, home);
    if (where == kOutside) left = std::min(left, p);
    stray[p] = where == kStray;
    strays_counted += where == kStray;
    return where;
  }
  // Rebuilds `strays` from the flags (after the positions changed); `count` strays are flagged.
  void collect_strays(long count) {
    strays.clear();
    if (count == 0) return;
    for (std::size_t p = 0; p < stray.size(); ++p)
      if (stray[p]) strays.push_back(static_cast<std::uint32_t>(p));
  }

 private:
  // every strip's part of a sum, made over the visited strips; this process's own parts
  template <class T, class Body>
  std::vector<T> own_parts(const T& zero, Body& body) const {
    std::vector<T> part(static_cast<std::size_t>(strips), zero);
#pragma omp parallel for schedule(dynamic, 1)
    for (long s = visit_lo; s < visit_hi; ++s) body(s, part[static_cast<std::size_t>(s)]);
    return std::vector<T>(part.begin() + own_lo, part.begin() + own_hi);
  }
  std::vector<long> order_[4];  // visit_order
};

}  // namespace pbx
