#pragma once
// Contact between deformable velocity fields at shared nodes. The law here is the `weld`
// (single-velocity) limit: every field at a node moves with the node's centre-of-mass velocity,
// which is what single-field MPM does. Frictional laws between fields plug in at this seam.
#include "grid/grid.hpp"

namespace pbx {

template <int D>
void weld_fields(Grid<D>& grid, int deformable, double mass_eps);

}  // namespace pbx
