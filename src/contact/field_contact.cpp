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

namespace {
// What one chunk of nodes hands to the ordered reduction.
template <int D>
struct PassSums {
  double work = 0;
  ContactTally<D> tally;
  PassSums& operator+=(const PassSums& o) {
    work += o.work;
    tally += o.tally;
    return *this;
  }
};
}  // namespace

template <int D>
double field_contact(Grid<D>& grid, const ContactMatrix& cm, int deformable, double dt, double mass_eps,
                     ContactTally<D>* tally) {
  if (deformable < 2) return 0.0;
  const long nn = grid.nodes();
  const double area = std::pow(grid.h, D - 1);  // contact area of a node (per metre of depth in 2-D)
  const double reach = cm.position_cutoff * grid.h;
  const std::size_t nf = static_cast<std::size_t>(deformable);
  PassSums<D> zero{0.0, ContactTally<D>(tally ? deformable : 0)};

  PassSums<D> sums = ordered_reduce(nn, zero, [&](long begin, long end) {
    PassSums<D> out = zero;
    double& work = out.work;
    // Half of the impulse d on field a, booked to the pair (a, partner): both sides of a pair
    // book the same exchange.
    auto book = [&](int a, int partner, const Vec<D>& d, double dn_abs, double dt_abs) {
      if (!tally) return;
      PairImpulse<D>& p = a < partner ? out.tally.at(a, partner) : out.tally.at(partner, a);
      p.on_first += a < partner ? Vec<D>(0.5 * d) : Vec<D>(-0.5 * d);
      p.normal += 0.5 * dn_abs;
      p.shear += 0.5 * dt_abs;
    };
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
          book(a, partner, d, 0.0, 0.0);
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
        book(a, partner, d, -dn, scale * tn);
        if (scale < 1.0 && cap > 0.0) {
          // Friction impulse times the mean of the tangential slip speeds before and after it
          // (exactly the kinetic energy the tangential exchange removes); half per field,
          // because both sides of a pair evaluate the same exchange.
          const Vec<D> v0 = pa / ma - pr / mr, v1 = (pa + d) / ma - (pr - d) / mr;
          const double s0 = (v0 - v0.dot(n) * n).norm(), s1 = (v1 - v1.dot(n) * n).norm();
          work += 0.25 * cap * (s0 + s1);
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
    return out;
  }, 1024);
  if (tally) *tally += sums.tally;
  return sums.work;
}

template void weld_fields<2>(Grid<2>&, int, double);
template void weld_fields<3>(Grid<3>&, int, double);
template double field_contact<2>(Grid<2>&, const ContactMatrix&, int, double, double, ContactTally<2>*);
template double field_contact<3>(Grid<3>&, const ContactMatrix&, int, double, double, ContactTally<3>*);

}  // namespace pbx
