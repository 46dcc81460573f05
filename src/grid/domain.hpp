#pragma once
// A domain: the box of grid nodes one worker owns, and the ghost layers around it that its
// particles' stencils also reach. Today the workers are the strips of one process
// (grid/strip_bins.hpp: a strip owns its node columns, and its particles' 3-node stencils reach one
// column beyond on each side); a domain decomposition over MPI ranks (issue 28) gives each rank such
// a box in every direction and exchanges the ghost layers' sums. The parity scheme of the strips
// is the statement that two strips of one parity have disjoint reach (`reach_overlaps`), checked by
// the strips' test rather than argued only in a comment.
#include <algorithm>
#include <array>

#include "grid/grid.hpp"

namespace pbx {

template <int D>
struct NodeBox {
  std::array<long, D> lo{}, hi{};  // node index ranges [lo, hi) per axis
  bool empty() const {
    for (int d = 0; d < D; ++d)
      if (hi[d] <= lo[d]) return true;
    return false;
  }
  long count() const {
    long c = 1;
    for (int d = 0; d < D; ++d) c *= std::max(0L, hi[d] - lo[d]);
    return c;
  }
  bool contains(const std::array<long, D>& ijk) const {
    for (int d = 0; d < D; ++d)
      if (ijk[d] < lo[d] || ijk[d] >= hi[d]) return false;
    return true;
  }
  bool overlaps(const NodeBox& o) const {
    for (int d = 0; d < D; ++d)
      if (std::min(hi[d], o.hi[d]) <= std::max(lo[d], o.lo[d])) return false;
    return true;
  }
};

template <int D>
struct Domain {
  NodeBox<D> owned;  // the nodes whose sums this worker completes: the lower corners of its cells
  // Node layers beyond `owned` that its particles' stencils reach, per side: a particle in cell c
  // (between nodes c and c + 1) has its 3-node stencil start at round(s) - 1 (grid/shape.hpp), so it
  // reaches nodes c - 1 .. c + 2 whichever kernel.
  long below = 1, above = 2;
  // The nodes its scatter may touch: the owned box widened by the ghost layers, within the grid.
  NodeBox<D> reach(const Grid<D>& g) const {
    NodeBox<D> r = owned;
    for (int d = 0; d < D; ++d) r.lo[d] = std::max(0L, r.lo[d] - below), r.hi[d] = std::min(g.n[d], r.hi[d] + above);
    return r;
  }
};

// Two domains whose scatters may touch one node: they must not scatter at the same time.
template <int D>
bool reach_overlaps(const Grid<D>& g, const Domain<D>& a, const Domain<D>& b) {
  return a.reach(g).overlaps(b.reach(g));
}

}  // namespace pbx
