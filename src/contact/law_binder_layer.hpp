#pragma once
// The binder_layer law at a node (contact/binder_layer.hpp holds its parameters): where both sides
// are bonded (mostly particles of a grain-grain contact) a spring on the displacement jump between
// them acts, backward Euler in the jump, J = dt k s / (1 + k dt^2 / m_red) per direction, with the
// shear capped at mu x the compressive normal traction (Eq. 7, S_a = 0); squeezed out past closure
// x t or torn open past t, and wherever a side is not bonded, Coulomb with the layer's friction.
// docs/theory/contact.md.
#include <algorithm>
#include <cmath>

#include "contact/law_coulomb.hpp"
#include "contact/node_contact.hpp"

namespace pbx {

// Displacement of a field at the node x_i from its mass-weighted sums: the displacement of its
// mass centre, carried to the node with the field's mean deformation gradient,
//   u(x_i) = (xbar - Xbar) + (I - Fbar^-1)(x_i - xbar),
// exact for any homogeneous deformation, so two bonded fields strained alike show no jump (the
// mass centres of two fields at a node lie about a cell apart: without the gradient term a strain
// eps would read as a jump eps * h).
template <int D>
Vec<D> field_displacement(double m, const Vec<D>& moff, const Vec<D>& mref, const Mat<D>& mdef, const Vec<D>& xi) {
  const Vec<D> xc = moff / m;
  const Mat<D> Fbar = mdef / m;
  return (xc - mref / m) + (Mat<D>::Identity() - Fbar.inverse()) * (xi - xc);
}

// What a binder layer between a and r does at the node.
enum class LayerState {
  coulomb,  // no spring here: squeezed out, torn open, or no interface area
  waits,    // the pass after P2G: the fields move on their own until the spring acts
  acts      // the spring's impulse d on a (-d on r)
};

template <int D>
struct LayerImpulse {
  LayerState state = LayerState::coulomb;
  Vec<D> d = Vec<D>::Zero();
  double jn = 0, jt = 0;  // |normal|, |tangential| impulse
  double work = 0;        // plastic work of a flowing layer over the step, J
  double energy = 0;      // the spring's energy at the end of the step, J
};

// The spring of a binder layer between a and r (both bonded), backward Euler in the jump.
template <int D>
LayerImpulse<D> layer_impulse(const LayerLaw& L, const Side<D>& a, const Side<D>& r, const Vec<D>& xi, double dt,
                              bool after_update) {
  LayerImpulse<D> out;
  // The displacements give the jump as a reference-configuration vector, X_a - X_r of the two
  // material points now at the node; the film closes by its current length, F (X_a - X_r), with F
  // the two sides' mean deformation gradient. Read in reference length the gap was 1/F too large
  // (a compressed pair's springs 0.5-1 % too stiff in the layered column, measured against the
  // particles' own gap), and a rotated pair mixed normal and tangential jumps by the rotation angle.
  const Vec<D> jump = ((a.F + r.F) / (a.m + r.m)) *
                      (field_displacement<D>(r.m, r.x, r.X, r.F, xi) - field_displacement<D>(a.m, a.x, a.X, a.F, xi));
  // Normal: from the contact normals the bonded particles carry (set at the start from the
  // direction of the touching grain, mapped with F^-T), a's towards r and r's towards a. Area: the
  // interface part of the volume gradients, 1/2 (g_a - g_r).n; the gradients alone also hold the
  // die walls and free surfaces at the edges of a contact, which tilt a gradient normal by up to
  // 55 degrees and add 40 % to the area there.
  const Vec<D> nl = a.N - r.N;
  const double nln = nl.norm();
  const Vec<D> nu = nln > 0.0 ? Vec<D>(nl / nln) : Vec<D>(Vec<D>::Zero());
  const double gln = 0.5 * std::abs((a.g - r.g).dot(nu));
  // A node without interface area (gln = 0: the particles' normals cancel) has no spring to act:
  // Coulomb, as for a squeezed-out layer (it used to get no contact at all).
  // The layer's 1/t at the node: the mean over the bonded particles of both sides (each carries
  // its contact's 1/t; a direct-stiffness law carries 1).
  const double inv_t = (a.t + r.t) / (a.b + r.b);
  // Outside its range the layer is gone: squeezed out past closure x t, or torn open past t (a
  // normal strain of 100 %); the pair is then Coulomb (inactive while apart). Without the tear the
  // spring pulled ever harder on fields that had parted, and a light field at the edge of a
  // grain's support was thrown: TATB particles inverted at 2.6-3.3 % strain at 353-373 K on the
  // paper specimen. A flowing layer (flow_stress/flow_factor) is never squeezed out: it keeps its
  // capped traction however far the grains pass into each other.
  const double jn = jump.dot(nu) * inv_t;
  const bool out_of_range = !L.binder.empty() && ((!L.flows() && -jn > L.closure) || jn > 1.0);
  if (!(gln > 0.0) || out_of_range) return out;
  if (!after_update) {
    out.state = LayerState::waits;
    return out;
  }
  out.state = LayerState::acts;
  // Backward Euler in the jump: the impulse J that the spring exerts over the step with the jump
  // at the end of it, s - dt J / m_red, where s = jump + dt (v_r - v_a) is the end-of-step jump
  // without it. Stable for any stiffness; sticks as k dt^2/m_red grows.
  const Vec<D>& n = nu;
  const double area = gln;
  const double mred = a.m * r.m / (a.m + r.m);
  const Vec<D> sv = jump + dt * (r.p / r.m - a.p / a.m);
  const double sn = sv.dot(n);
  const Vec<D> st = sv - sn * n;
  const double kn = area * L.kn * inv_t, kt = area * L.kt * inv_t;
  const double cn = 1.0 / (1.0 + kn * dt * dt / mred), ct = 1.0 / (1.0 + kt * dt * dt / mred);
  double Jn = dt * kn * cn * sn;
  Vec<D> Jt = (dt * kt * ct) * st;
  if (L.flows() && sn < 0.0) {
    // The film flows at the cap: the traction stays there and the closure beyond the cap's
    // elastic part is plastic (booked as dissipated work).
    const double lim = dt * area * L.flow_cap();
    if (-Jn > lim) {
      Jn = -lim;
      const double closing = jump.dot(n) - (sn - dt * Jn / mred);
      out.work = (lim / dt) * std::max(0.0, closing);
    }
  }
  // Eq. 7 with S_a = 0 on the layer: its shear traction is at most friction x its compressive
  // normal traction (sn < 0: r closes on a), none in tension. The cap acts on the spring's total
  // tangential jump (a node keeps no slip history), so the capped response is nonlinear elastic:
  // it dissipates nothing, and unloading follows it back.
  if (L.shear_cap) {
    const double cap = sn < 0.0 ? L.friction * std::abs(Jn) : 0.0, jt = Jt.norm();
    if (jt > cap) Jt *= jt > 0.0 ? cap / jt : 0.0;
  }
  out.d = Jn * n + Jt;
  out.jn = std::abs(Jn);
  out.jt = Jt.norm();
  // energy held at the end of the step, F^2 / 2k per spring with F = J/dt (from the impulse, so a
  // capped layer holds cap^2 / 2k, not the energy of its whole jump)
  out.energy = 0.5 * (Jn * Jn / (dt * dt * kn) + (kt > 0.0 ? Jt.squaredNorm() / (dt * dt * kt) : 0.0));
  return out;
}

// film = "bonds": the force of a pair's spring on its first particle (the second takes the
// opposite), N per metre of depth in 2-D, and the energy it holds. s is the change of the pair's
// separation since the start, n0 its reference direction, coef its share of the film per unit
// modulus (LayerBond::coef): f = k_n s_n n0 + k_t s_t with the node law's Eq. 7 cap, shear at most
// friction x the compressive normal force and none in tension, on the pair's total tangential change
// (a pair keeps no slip history, as a node keeps none: nonlinear elastic, dissipating nothing).
// Energy F^2 / 2k per spring, so a capped pair holds cap^2 / 2k_t.
template <int D>
struct BondForce {
  Vec<D> f;
  double energy = 0;
};

template <int D>
BondForce<D> bond_force(const LayerLaw& L, double coef, const Vec<D>& n0, const Vec<D>& s) {
  const double kn = coef * L.kn, kt = coef * L.kt, sn = s.dot(n0), fn = kn * sn;
  Vec<D> ft = kt * (s - sn * n0);
  if (L.shear_cap) {
    const double cap = sn < 0.0 ? -L.friction * fn : 0.0, m = ft.norm();
    if (m > cap) ft *= m > 0.0 ? cap / m : 0.0;
  }
  BondForce<D> out;
  out.f = fn * n0 + ft;
  out.energy = 0.5 * (fn * fn / kn + (kt > 0.0 ? ft.squaredNorm() / kt : 0.0));
  return out;
}

struct BinderLayerLaw {
  static constexpr bool needs_normal = true;
  const LayerLaw* layer = nullptr;  // the layer's parameters and its stiffnesses now (LayerLaw::at_time)

  template <int D>
  [[gnu::always_inline]] Exchange<D> exchange(const NodeContact<D>& c) const {
    if (c.layers && c.a.bonded() && c.r.bonded()) {
      const LayerImpulse<D> J = layer_impulse<D>(*layer, c.a, c.r, c.xi, c.dt, c.after_update);
      // film = "bonds": the particle pairs carry the film (Solver::bond_impulses); the node leaves the
      // two bonded fields alone until the layer is squeezed out or torn
      if (J.state == LayerState::waits || (J.state == LayerState::acts && layer->bonds)) return Exchange<D>{};
      if (J.state == LayerState::acts) {
        Exchange<D> e;
        e.acts = true;
        e.spring = true;
        e.d = J.d;
        e.dn_abs = J.jn;
        e.dt_abs = J.jt;
        // half of the spring's energy and work per side: both sides evaluate the same spring
        e.energy = J.energy;
        e.work = 0.5 * J.work;
        return e;
      }
    }
    // squeezed out, torn open, without interface area, or a side not bonded
    return CoulombLaw{layer->friction, 0.0}.exchange(c);
  }
};

}  // namespace pbx
