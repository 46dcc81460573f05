#pragma once
// Coulomb friction with an optional shear adhesion (the paper's Eq. 6-7 in Nairn's momentum form):
// contact where a approaches r (d_n = stick . n < 0) and, with the position check on, where their
// mass centres are within its reach; the impulse on a is
//   d_n n + dp_t min(1, (S_a A dt - mu d_n) / |dp_t|),
// i.e. the normal part of the stick impulse and the tangential part capped by friction (plus
// adhesion). Frictionless is mu = S_a = 0, Coulomb S_a = 0. Against a rigid body (infinite mass):
//   approaching (v_rel . n < 0): dp = -m (v_rel . n) n - m v_t min(1, mu |v_rel . n| / |v_t|).
#include <algorithm>
#include <cmath>

#include "contact/node_contact.hpp"

namespace pbx {

struct CoulombLaw {
  static constexpr bool needs_normal = true;
  double friction = 0;  // mu
  double adhesion = 0;  // S_a, Pa

  template <int D>
  [[gnu::always_inline]] Exchange<D> exchange(const NodeContact<D>& c) const {
    Exchange<D> e;
    const Vec<D>& n = c.n;
    const double dn = c.stick.dot(n);
    if (dn >= 0.0) return e;  // separating: no contact
    if (c.apart()) return e;  // surfaces apart
    const Vec<D> t = c.stick - dn * n;
    const double tn = t.norm();
    const double cap = adhesion * c.area * c.dt - friction * dn;
    const double scale = tn > cap ? cap / tn : 1.0;
    e.acts = true;
    e.d = dn * n + scale * t;
    e.dn_abs = -dn;
    e.dt_abs = scale * tn;
    if (scale < 1.0 && cap > 0.0) {
      // Friction impulse times the mean of the tangential slip speeds before and after it
      // (exactly the kinetic energy the tangential exchange removes); half per field, because
      // both sides of a pair evaluate the same exchange. Within 0.1-5 % of mu N d on the sliding
      // block (test_inclined_plane.cpp); in quasi-static contact the slip before the exchange
      // holds this step's internal-force increment, which the stress work never sees, and the
      // measure over-books: 1.7x the energy friction removed in the two-grain die test (the
      // impulse times the slip after the exchange closes that balance to 1 % but is 7 % under
      // mu N d on the block; 2026-12-05). The column is an upper bound there.
      const double ma = c.a.m, mr = c.r.m;
      const Vec<D> v0 = c.a.p / ma - c.r.p / mr, v1 = (c.a.p + e.d) / ma - (c.r.p - e.d) / mr;
      const double s0 = (v0 - v0.dot(n) * n).norm(), s1 = (v1 - v1.dot(n) * n).norm();
      e.work = 0.25 * cap * (s0 + s1);
    }
    return e;
  }

  // Against a rigid body whose outward normal is n (adhesion does not act on rigid faces).
  template <int D>
  [[gnu::always_inline]] RigidExchange<D> rigid(double m, const Vec<D>& vrel, const Vec<D>& n) const {
    RigidExchange<D> e;
    const double vn = vrel.dot(n);
    if (vn >= 0.0) return e;  // separating or sliding along: free
    const Vec<D> vt = vrel - vn * n;
    const double vt_norm = vt.norm();
    e.acts = true;
    e.dp = -m * vn * n;
    if (friction > 0 && vt_norm > 0) {
      const double cap = friction * (-vn);
      const double scale = std::min(1.0, cap / vt_norm);
      e.dp -= m * scale * vt;
      // Energy dissipated by sliding: the friction impulse m cap times the mean of the slip
      // speeds before (vt_norm) and after (vt_norm - cap) it, i.e. exactly the kinetic energy
      // the tangential impulse removes at the node.
      if (scale < 1.0) e.friction_work = m * cap * (vt_norm - 0.5 * cap);
    }
    return e;
  }
};

}  // namespace pbx
