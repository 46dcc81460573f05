#pragma once
// Which particles' next P2G must scatter what the contact stages read: the mass-centre offsets
// (the rigid bodies' contact gate) and the field contact's data (volume gradients, binder-layer
// sums, offsets). A particle is marked by its stencil's base node; where a mask is not valid this
// step, every particle scatters everything. The sums at every node a contact stage reads are
// unchanged to the bit (tests/engine/test_offset_mask.cpp, test_contact_mask.cpp). 2-D, fused USL
// pass only.
#include <algorithm>
#include <cstdint>
#include <limits>
#include <vector>

#include "bodies/body_presence.hpp"
#include "bodies/rigid_body.hpp"
#include "grid/grid.hpp"
#include "grid/shape.hpp"

namespace pbx {

template <int D>
class ContactScatterMasks {
 public:
  // Which particles' next P2G must carry mass-centre offsets. Where the rigid-body contact gate is
  // their only reader (no field position check, no binder_layer sums), only the nodes where a body
  // is present at the next step need them, and those lie within one node of this step's nodes as
  // long as no body moves half a cell in the step. A particle is marked by its stencil's base node:
  // the base of every 3 x 3 block that meets such a node. The offsets are 2 of the 7 nodal sums
  // the P2G scatters per node; in the die this leaves them out for all but a few particles near
  // the walls and the punch. The sums at the nodes the gate reads are unchanged to the bit.
  template <Kernel K>
  void mark_offsets(const Grid<D>& g, const std::vector<RigidBody<D>>& bodies, const BodyPresence<D>& presence,
                    const HalfWidth& a, double t, double dt, bool usl) {
    offset_bases_valid_ = false;
    if constexpr (D == 2) {
      // only the fused USL pass reads the mask
      // (where the field contact reads the offsets too, mark_contact gates them for it)
      if (!usl || bodies.empty()) return;
      const double inv_h = 1.0 / g.h;
      for (const auto& body : bodies)
        if (body.moving()) {
          const Vec<D> u = body.displacement_at(t + dt) - body.displacement_at(t);
          if (!(u.cwiseAbs().maxCoeff() < 0.5 * g.h)) return;  // mark every particle this step
        }
      const long nx = g.n[0], ny = g.n[1];
      // bases i with [i, i + 2] meeting [lo, hi], per axis, clamped to the grid
      auto mark = [&](std::vector<std::uint8_t>& m, long x_lo, long x_hi, long y_lo, long y_hi) {
        for (long y = std::max(0L, y_lo - 2); y <= std::min(ny - 1, y_hi); ++y)
          for (long x = std::max(0L, x_lo - 2); x <= std::min(nx - 1, x_hi); ++x)
            m[static_cast<std::size_t>(x + y * nx)] = 1;
      };
      if (static_offset_bases_.empty()) {  // static bodies: their nodes, once
        static_offset_bases_.assign(static_cast<std::size_t>(g.nodes()), 0);
        for (std::size_t b = 0; b < bodies.size(); ++b)
          if (!bodies[b].moving())
            for (const auto& [i, S] : presence.static_presence(b))
              mark(static_offset_bases_, i % nx, i % nx, i / nx, i / nx);
      }
      offset_bases_ = static_offset_bases_;
      // moving bodies: the nodes of each rigid particle's stencil, grown by one node
      for (const auto& body : bodies)
        if (body.moving())
          for (const auto& x : body.x) {
            const Stencil<D> st = make_stencil<D, K>(x, g.origin, inv_h, a);
            mark(offset_bases_, st.base[0] - 1, st.base[0] + 3, st.base[1] - 1, st.base[1] + 3);
          }
      offset_bases_valid_ = true;
    }
  }

  // The stencil base nodes of the particles whose next P2G must scatter what the field contact
  // reads (volume gradients, binder-layer sums, mass-centre offsets): the contact acts only at nodes
  // where two or more fields have mass, and the sums there must be whole. A particle moves less than
  // a cell per step (the fused pass checks it and re-runs a full P2G otherwise), so its stencil base
  // moves by at most one node: a node can hold two fields next step only if two fields are present
  // within one node of it now (a candidate), and a particle needs the data if its next stencil
  // [b, b + 2] holds a candidate. The sums at every node the contact reads are unchanged to the bit;
  // deep inside a grain (most particles at fine cells) the particles scatter only mass, momentum and
  // force. 2-D, fused USL pass only.
  // field_contact: the fused USL pass, with a contact law other than weld between two or more fields.
  // `seen_lo`, `seen_hi`: the node lines (x) whose masses are complete here (a rank of a decomposed
  // run sees only its own); a node beyond them is taken as a candidate, which makes more particles
  // scatter the contact's data and changes no sum the contact reads (the masks only ever leave out
  // particles whose stencil meets no node of two fields; ContactMask.BoundedMarkingMarksAtLeast...).
  void mark_contact(const Grid<D>& g, int nf, bool field_contact, long seen_lo = 0,
                    long seen_hi = std::numeric_limits<long>::max()) {
    contact_bases_valid_ = false;
    if constexpr (D == 2) {
      if (!field_contact || nf < 2 || nf > 64) return;
      const long nx = g.n[0], ny = g.n[1], nn = g.nodes();
      // Each pass computes only the columns whose result can differ from its value beyond the seen
      // lines (every field there: a candidate, a marked base), so a rank's cost follows its own
      // columns, not the whole grid's; the marks are those of the passes over every column.
      const long x0 = std::max(0L, seen_lo), x1 = std::min(nx - 1, seen_hi);
      field_bits_.assign(static_cast<std::size_t>(nn), ~std::uint64_t{0});
      std::uint64_t* bits = field_bits_.data();
#pragma omp parallel for schedule(static)
      for (long y = 0; y < ny; ++y)
        for (long x = x0; x <= x1; ++x) {
          const long i = x + y * nx;
          std::uint64_t b = 0;
          for (int f = 0; f < nf; ++f)
            if (g.mass[g.at(f, i)] > 0.0) b |= std::uint64_t{1} << f;
          bits[i] = b;
        }
      // candidates: two or more fields within one node (a 3 x 3 OR, then a count)
      std::vector<std::uint8_t>& cand = candidate_;
      cand.assign(static_cast<std::size_t>(nn), 1);
      const long cx0 = std::max(0L, x0 - 1), cx1 = std::min(nx - 1, x1 + 1);
#pragma omp parallel for schedule(static)
      for (long y = 0; y < ny; ++y)
        for (long x = cx0; x <= cx1; ++x) {
          std::uint64_t u = 0;
          for (long yy = std::max(0L, y - 1); yy <= std::min(ny - 1, y + 1); ++yy)
            for (long xx = std::max(0L, x - 1); xx <= std::min(nx - 1, x + 1); ++xx) u |= bits[xx + yy * nx];
          cand[static_cast<std::size_t>(x + y * nx)] = (u & (u - 1)) != 0;  // more than one bit set
        }
      // bases whose 3 x 3 stencil holds a candidate
      contact_bases_.assign(static_cast<std::size_t>(nn), 1);
      const long bx0 = std::max(0L, cx0 - 2);
#pragma omp parallel for schedule(static)
      for (long y = 0; y < ny; ++y)
        for (long x = bx0; x <= cx1; ++x) {
          std::uint8_t m = 0;
          for (long yy = y; yy <= std::min(ny - 1, y + 2); ++yy)
            for (long xx = x; xx <= std::min(nx - 1, x + 2); ++xx) m |= cand[static_cast<std::size_t>(xx + yy * nx)];
          contact_bases_[static_cast<std::size_t>(x + y * nx)] = m;
        }
      contact_bases_valid_ = true;
    }
  }

  // The masks the next P2G reads, or nullptr where every particle scatters everything.
  const std::uint8_t* offset_bases() const { return offset_bases_valid_ ? offset_bases_.data() : nullptr; }
  const std::uint8_t* contact_bases() const { return contact_bases_valid_ ? contact_bases_.data() : nullptr; }
  // A particle jumped a cell: the contact mask no longer covers its next stencil.
  void drop_contact() { contact_bases_valid_ = false; }
  bool contact_valid() const { return contact_bases_valid_; }

 private:
  std::vector<std::uint8_t> offset_bases_, static_offset_bases_;
  bool offset_bases_valid_ = false;
  std::vector<std::uint8_t> contact_bases_, candidate_;
  std::vector<std::uint64_t> field_bits_;
  bool contact_bases_valid_ = false;
};

}  // namespace pbx
