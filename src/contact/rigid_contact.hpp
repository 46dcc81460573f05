#pragma once
// Contact between deformable fields and rigid bodies at grid nodes (the rigid body is the
// infinite-mass limit of the multi-field momentum law): at a node where body b is present and
// deformable field a has mass, with n the body's outward normal and v_rel = v_a - v_b,
//   approaching (v_rel . n < 0):  normal impulse  dp_n = -m_a (v_rel . n) n   (stops penetration)
//                                 tangential     dp_t = -m_a v_t min(1, mu |v_rel . n| / |v_t|)
// (Coulomb: stick while |v_t| <= mu |v_n|, else slide with tangential impulse mu x normal impulse).
// Nodes at or behind the body's face (x_i . n <= face) take part, and nodes in front of it whose
// field mass centre lies within `cutoff` cells of the face (position check).
// A `stick` body always imposes v_a = v_b. Impulses are added to the body's record so that the
// reaction force is exactly the momentum exchanged.
#include <functional>
#include <vector>

#include "bodies/rigid_body.hpp"
#include "grid/grid.hpp"
#include "grid/strip_bins.hpp"

namespace pbx {

template <int D>
struct RigidContactResult {
  std::vector<Vec<D>> impulse;  // per body, given to the specimen
  std::vector<double> work;     // per body, work done on the specimen (impulse . v_body)
  std::vector<double> friction_work;
};

// Applies the rigid contacts on the momenta `grid.mom` of fields [0, deformable), and hands the
// impulses, work and friction work per body to `book` (if set; to be recorded when the pass
// changes particle momentum). `body_nodes` lists, ascending, every node where some body is present
// (grid.presence > 0); the other nodes are not visited. The sums are taken strip by strip over
// `strips` (grid/strip_bins.hpp; null: the grid's strips, all this process's), so they do not depend
// on the list, the thread count or, in a decomposed run, the rank count; `book` receives them at
// once, or where `strips` defer their sums (StripBins::fold_then), at the next settle.
template <int D>
void rigid_contact(Grid<D>& grid, std::vector<RigidBody<D>>& bodies, int deformable, double t, double mass_eps,
                   const std::vector<long>& body_nodes, const std::function<void(const RigidContactResult<D>&)>& book,
                   const StripBins* strips = nullptr);

}  // namespace pbx
