#pragma once
// The weld law: field a and the rest move together at the node (the single-velocity limit for the
// pair); against a rigid body, a "stick" body: the field takes the body's velocity.
#include "contact/node_contact.hpp"

namespace pbx {

struct WeldLaw {
  static constexpr bool needs_normal = false;
  template <int D>
  [[gnu::always_inline]] Exchange<D> exchange(const NodeContact<D>& c) const {
    Exchange<D> e;
    e.acts = true;
    e.d = c.stick;
    return e;
  }
  // m: the field's mass at the node; vrel: its velocity relative to the body
  template <int D>
  [[gnu::always_inline]] RigidExchange<D> rigid(double m, const Vec<D>& vrel) const {
    RigidExchange<D> e;
    e.acts = true;
    e.dp = -m * vrel;
    return e;
  }
};

}  // namespace pbx
