#pragma once
// The interface of a contact law (docs/extending.md "A contact law"). At a grid node where field a
// meets the rest r of the fields (the sum of every other field there), the field contact pass builds
// a NodeContact and asks the pair's law for the Exchange: the momentum impulse d on a (the rest
// receives -d). Against a rigid body (the infinite-mass limit, contact/rigid_contact.cpp) the law is
// asked for the impulse on the field from its mass and its velocity relative to the body.
//
// The laws (one file each): contact/law_weld.hpp, contact/law_coulomb.hpp (frictionless, Coulomb,
// adhesion), contact/law_binder_layer.hpp; a law registered at run time: contact/law_registry.hpp.
#include "contact/binder_layer.hpp"
#include "contact/layer_data.hpp"
#include "core/tensor.hpp"
#include "grid/grid.hpp"

namespace pbx {

// One side of an exchange at a node: one field, or the sum of several (the rest of a field).
template <int D>
struct Side {
  double m = 0;
  Vec<D> p = Vec<D>::Zero(), g = Vec<D>::Zero(), x = Vec<D>::Zero();
  Vec<D> X = Vec<D>::Zero(), N = Vec<D>::Zero();  // binder_layer sums
  Mat<D> F = Mat<D>::Zero();
  double b = 0, t = 0;
  // field entry k of the grid (and of the binder-layer sums, when the run has them)
  void add(const Grid<D>& grid, long k, const LayerSums<D>* layers) {
    m += grid.mass[k];
    p += grid.mom[k];
    g += grid.vgrad[k];
    x += grid.moff[k];
    if (layers) {
      X += layers->mref[k];
      F += layers->mdef[k];
      b += layers->mbond[k];
      t += layers->minvt[k];
      N += layers->mnorm[k];
    }
  }
  // the sums of another side, in the order add() takes a grid entry's
  Side& operator+=(const Side& o) {
    m += o.m;
    p += o.p;
    g += o.g;
    x += o.x;
    X += o.X;
    F += o.F;
    b += o.b;
    t += o.t;
    N += o.N;
    return *this;
  }
  // most of its mass is bonded particles (of a grain-grain contact)
  bool bonded() const { return b >= 0.5 * m; }
};

// What a law sees at a node: field a against the rest r.
template <int D>
struct NodeContact {
  const Side<D>& a;   // field a's own sums (mass, momentum, volume gradient, mass-centre offset, ...)
  const Side<D>& r;   // the rest's sums
  Vec<D> stick;       // the impulse that makes a and r move together, (m_a p_r - m_r p_a)/(m_a + m_r)
  Vec<D> n;           // a's outward unit normal towards r (contact normal option of the deck)
  double area;        // contact area of the node, h^(D-1) (per metre of depth in 2-D)
  double dt;          // the step, s
  double reach;       // position check: contact only where the mass centres are closer than this along n, m (0: off)
  Vec<D> xi;          // the node's position relative to the grid origin, m
  bool layers;        // the grid carries the binder-layer sums
  bool after_update;  // the pass after the grid update (the pass after P2G is "before")
  // The mass centres of a and r lie farther apart along n than the position check's reach.
  bool apart() const { return reach > 0.0 && (r.x / r.m - a.x / a.m).dot(n) > reach; }
};

// What a law gives at a node.
template <int D>
struct Exchange {
  bool acts = false;  // false: no exchange (separating, apart, no normal, a spring waiting)
  Vec<D> d = Vec<D>::Zero();
  double dn_abs = 0, dt_abs = 0;  // |normal|, |tangential| impulse booked to the pair
  double work = 0;                // this side's share of the dissipated work, J
  double energy = 0;              // the energy a spring holds at the end of the step (each side books half), J
  bool spring = false;            // a binder-layer spring acted (field_contact may hand it through the particles)
};

// What a law gives against a rigid body at a node: the impulse on the field and the energy
// dissipated by sliding.
template <int D>
struct RigidExchange {
  bool acts = false;
  Vec<D> dp = Vec<D>::Zero();
  double friction_work = 0;
};

}  // namespace pbx
