#pragma once
// Background grid with per-field nodal arrays: a node carries one velocity field per contact
// field (deformable fields first, then one per rigid body). Field f of node i lives at f*nodes()+i.
#include <array>
#include <vector>

#include "core/tensor.hpp"

namespace pbx {

template <int D>
struct Grid {
  Vec<D> origin = Vec<D>::Zero();  // position of node 0, m
  double h = 0;                    // cell size, m
  std::array<long, D> n{};         // nodes per axis
  std::array<long, D> stride{};    // node index step per axis
  int fields = 0;

  // Per field and node. For rigid fields `mass` holds the rigid body's presence (sum of S_ip of
  // its particles), not a mass.
  std::vector<double> mass;
  std::vector<Vec<D>> mom;        // momentum after P2G, then after the contact passes
  std::vector<Vec<D>> mom0;       // momentum as interpolated (FLIP increment base)
  std::vector<Vec<D>> moff;       // sum S m (x_p - origin): mass centre of the field near the node
  std::vector<Vec<D>> vgrad;      // sum V_p grad S: volume gradient of the field (contact normals)
  std::vector<Vec<D>> force;      // internal + external force
  std::vector<Vec<D>> vel;        // final nodal velocity of the step (v = p/m)
  std::vector<Vec<D>> dvel;       // velocity increment of the step (FLIP)

  long nodes() const {
    long c = 1;
    for (int d = 0; d < D; ++d) c *= n[d];
    return c;
  }
  long at(int field, long node) const { return field * nodes() + node; }
  Vec<D> position(long node) const {
    Vec<D> x;
    for (int d = 0; d < D; ++d) {
      x[d] = origin[d] + h * static_cast<double>(node % n[d]);
      node /= n[d];
    }
    return x;
  }

  void allocate(int nfields) {
    fields = nfields;
    stride[0] = 1;
    for (int d = 1; d < D; ++d) stride[d] = stride[d - 1] * n[d - 1];
    const std::size_t size = static_cast<std::size_t>(nfields) * static_cast<std::size_t>(nodes());
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
