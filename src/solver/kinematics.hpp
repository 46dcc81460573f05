#pragma once
// The particles' deformation gradient over one step, F_{n+1} = (I + dt L) F_n, L the velocity
// gradient gathered from the grid (paper Section 2.1, the update after G2P). The increment acts
// on the left: it maps the current configuration, so stretching and then rotating a body gives
// R U, not U R. J = det F is the same either way; in this code the order matters for the mean
// deformation gradient that the binder-layer law reads a jump with (contact/field_contact.cpp).
#include "core/tensor.hpp"

namespace pbx {

template <int D>
inline Mat<D> advance_deformation_gradient(const Mat<D>& F, const Mat<D>& L, double dt) {
  return (Mat<D>::Identity() + dt * L) * F;
}

}  // namespace pbx
