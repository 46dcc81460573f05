#pragma once
// Background grid with per-field nodal arrays: a node carries one velocity field per contact
// field (deformable fields first, then one per rigid body). Deformable field f of node i lives at
// f*nodes()+i in the nodal arrays. A rigid field needs no mass, momentum or force (its velocity is
// prescribed): it keeps only the body's presence at the node, in `presence`.
#include <array>
#include <vector>

#include "core/tensor.hpp"
#include "grid/shape.hpp"

namespace pbx {

template <int D>
struct Grid {
  Vec<D> origin = Vec<D>::Zero();  // position of node 0, m
  double h = 0;                    // cell size, m
  std::array<long, D> n{};         // nodes per axis
  std::array<long, D> stride{};    // node index step per axis
  int fields = 0;                  // all velocity fields: deformable, then rigid
  int deformable = 0;              // fields with full nodal arrays (the first `deformable` fields)
  ClampedNodes<D> clamped;         // fixed boundaries of the bspline2 basis (the die's walls), none by default

  // Per deformable field and node.
  std::vector<double> mass;
  std::vector<Vec<D>> mom;    // momentum after P2G, then after the contact passes
  std::vector<Vec<D>> mom0;   // momentum as interpolated (FLIP increment base)
  std::vector<Vec<D>> moff;   // sum S m (x_p - origin): mass centre of the field near the node
  std::vector<Vec<D>> vgrad;  // sum V_p grad S: volume gradient of the field (contact normals)
  std::vector<Vec<D>> force;  // internal + external force
  std::vector<Vec<D>> vel;    // final nodal velocity of the step (v = p/m)
  std::vector<Vec<D>> dvel;   // velocity increment of the step (FLIP)
  // Per rigid field and node: the body's presence (sum of S_ip over its rigid particles), at
  // (field - deformable)*nodes()+i.
  std::vector<double> presence;

  long nodes() const {
    long c = 1;
    for (int d = 0; d < D; ++d) c *= n[d];
    return c;
  }
  long at(int field, long node) const { return field * nodes() + node; }
  double rigid_presence(int field, long node) const {
    return presence[static_cast<std::size_t>((field - deformable) * nodes() + node)];
  }
  Vec<D> position(long node) const {
    Vec<D> x;
    for (int d = 0; d < D; ++d) {
      x[d] = origin[d] + h * static_cast<double>(node % n[d]);
      node /= n[d];
    }
    return x;
  }

  void allocate(int deformable_fields, int rigid_fields = 0) {
    fields = deformable_fields + rigid_fields;
    deformable = deformable_fields;
    stride[0] = 1;
    for (int d = 1; d < D; ++d) stride[d] = stride[d - 1] * n[d - 1];
    const std::size_t size = static_cast<std::size_t>(deformable_fields) * static_cast<std::size_t>(nodes());
    presence.assign(static_cast<std::size_t>(rigid_fields) * static_cast<std::size_t>(nodes()), 0.0);
    mass.assign(size, 0.0);
    mom.assign(size, Vec<D>::Zero());
    mom0.assign(size, Vec<D>::Zero());
    moff.assign(size, Vec<D>::Zero());
    vgrad.assign(size, Vec<D>::Zero());
    force.assign(size, Vec<D>::Zero());
    vel.assign(size, Vec<D>::Zero());
    dvel.assign(size, Vec<D>::Zero());
  }
};

}  // namespace pbx
