#include "contact/field_contact.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

#include "core/parallel.hpp"

namespace pbx {

template <int D>
void weld_fields(Grid<D>& grid, int deformable, double mass_eps) {
  if (deformable < 2) return;
  const long nn = grid.nodes();
#pragma omp parallel for schedule(static)
  for (long i = 0; i < nn; ++i) {
    double m = 0;
    int present = 0;
    Vec<D> p = Vec<D>::Zero();
    for (int f = 0; f < deformable; ++f) {
      const long k = grid.at(f, i);
      if (grid.mass[k] > mass_eps) {
        m += grid.mass[k];
        p += grid.mom[k];
        ++present;
      }
    }
    if (present < 2) continue;
    const Vec<D> vcm = p / m;
    for (int f = 0; f < deformable; ++f) {
      const long k = grid.at(f, i);
      if (grid.mass[k] > mass_eps) grid.mom[k] = grid.mass[k] * vcm;
    }
  }
}

namespace {

// Outward unit normal of field a against the rest r (grid.vgrad = sum V_p grad S_ip points out of a field); zero when the gradients give no direction.
template <int D>
Vec<D> contact_normal(ContactNormal mode, const Vec<D>& ga, const Vec<D>& gr, bool a_wins_tie) {
  Vec<D> n = Vec<D>::Zero();
  switch (mode) {
    case ContactNormal::dominant: {
      const double na = ga.squaredNorm(), nr = gr.squaredNorm();
      n = (na > nr || (na == nr && a_wins_tie)) ? Vec<D>(ga) : Vec<D>(-gr);
      break;
    }
    case ContactNormal::average: n = ga - gr; break;
    case ContactNormal::own: n = ga; break;
  }
  const double len = n.norm();
  return len > 0.0 ? Vec<D>(n / len) : Vec<D>(Vec<D>::Zero());
}

}  // namespace

template <int D>
double field_contact(Grid<D>& grid, const ContactMatrix& cm, int deformable, double dt, double mass_eps) {
  if (deformable < 2) return 0.0;
  const long nn = grid.nodes();
  const double area = std::pow(grid.h, D - 1);  // contact area of a node (per metre of depth in 2-D)
  const double reach = cm.position_cutoff * grid.h;
  const std::size_t nf = static_cast<std::size_t>(deformable);

  return ordered_reduce(nn, 0.0, [&](long begin, long end) {
    double work = 0;
    std::vector<int> present;
    std::vector<Vec<D>> dp(nf);
    present.reserve(nf);
    for (long i = begin; i < end; ++i) {
      present.clear();
      for (int f = 0; f < deformable; ++f)
        if (grid.mass[grid.at(f, i)] > mass_eps) present.push_back(f);
      if (present.size() < 2) continue;

      double mtot = 0;
      for (int a : present) mtot += grid.mass[grid.at(a, i)];

      for (std::size_t ia = 0; ia < present.size(); ++ia) {
        const int a = present[ia];
        const long ka = grid.at(a, i);
        const double ma = grid.mass[ka];
        const Vec<D>& pa = grid.mom[ka];
        // The rest r: every other field at the node, summed explicitly (not P - p_a) so that a
        // two-field node gets exactly opposite impulses.
        double mr = 0;
        Vec<D> pr = Vec<D>::Zero(), gr = Vec<D>::Zero(), xr = Vec<D>::Zero();
        int partner = -1;
        double mpartner = -1;
        for (int b : present) {
          if (b == a) continue;
          const long kb = grid.at(b, i);
          mr += grid.mass[kb];
          pr += grid.mom[kb];
          gr += grid.vgrad[kb];
          xr += grid.moff[kb];
          if (grid.mass[kb] > mpartner) {
            mpartner = grid.mass[kb];
            partner = b;
          }
        }
        const Vec<D> stick = (ma * pr - mr * pa) / (ma + mr);
        const PairLaw& law = cm(a, partner);
        Vec<D>& d = dp[static_cast<std::size_t>(ia)];
        if (law.law == ContactLaw::weld) {
          d = stick;
          continue;
        }
        d.setZero();
        const Vec<D> n = contact_normal<D>(cm.normal, grid.vgrad[ka], gr, a < partner);
        if (n.isZero()) continue;
        const double dn = stick.dot(n);
        if (dn >= 0.0) continue;  // separating: no contact
        if (reach > 0.0 && (xr / mr - grid.moff[ka] / ma).dot(n) > reach) continue;  // surfaces apart
        const Vec<D> t = stick - dn * n;
        const double tn = t.norm();
        double cap = 0;
        if (law.law == ContactLaw::coulomb || law.law == ContactLaw::adhesion)
          cap = law.adhesion * area * dt - law.friction * dn;
        const double scale = tn > cap ? cap / tn : 1.0;
        d = dn * n + scale * t;
        if (scale < 1.0 && cap > 0.0) {
          // Friction impulse times the tangential slip velocity left after it; half per field,
          // because both sides of a pair evaluate the same exchange.
          const Vec<D> va = (pa + d) / ma, vr = (pr - d) / mr;
          const Vec<D> slip = (va - vr) - (va - vr).dot(n) * n;
          work += 0.5 * cap * slip.norm();
        }
      }
      // Exact momentum balance at the node (round-off and 3+ field nodes).
      Vec<D> residual = Vec<D>::Zero();
      for (std::size_t ia = 0; ia < present.size(); ++ia) residual += dp[ia];
      for (std::size_t ia = 0; ia < present.size(); ++ia) {
        const long ka = grid.at(present[ia], i);
        grid.mom[ka] += dp[ia] - (grid.mass[ka] / mtot) * residual;
      }
    }
    return work;
  }, 1024);
}

template void weld_fields<2>(Grid<2>&, int, double);
template void weld_fields<3>(Grid<3>&, int, double);
template double field_contact<2>(Grid<2>&, const ContactMatrix&, int, double, double);
template double field_contact<3>(Grid<3>&, const ContactMatrix&, int, double, double);

}  // namespace pbx
