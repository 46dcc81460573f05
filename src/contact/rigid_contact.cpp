#include "contact/rigid_contact.hpp"

#include <algorithm>
#include <cmath>

#include "contact/law_coulomb.hpp"
#include "contact/law_weld.hpp"
#include "core/parallel.hpp"

namespace pbx {

namespace {
template <int D>
struct BodySums {
  std::vector<Vec<D>> impulse;
  std::vector<double> work, friction;
  explicit BodySums(std::size_t nb = 0) : impulse(nb, Vec<D>::Zero()), work(nb, 0.0), friction(nb, 0.0) {}
  BodySums& operator+=(const BodySums& o) {
    for (std::size_t b = 0; b < impulse.size(); ++b) {
      impulse[b] += o.impulse[b];
      work[b] += o.work[b];
      friction[b] += o.friction[b];
    }
    return *this;
  }
  template <class F>
  void each_double(F&& f) {
    for (std::size_t b = 0; b < impulse.size(); ++b) {
      for (int d = 0; d < D; ++d) f(impulse[b][d]);
      f(work[b]);
      f(friction[b]);
    }
  }
};
}  // namespace

template <int D>
void rigid_contact(Grid<D>& grid, std::vector<RigidBody<D>>& bodies, int deformable, double t, double mass_eps,
                   const std::vector<long>& body_nodes, const std::function<void(const RigidContactResult<D>&)>& book,
                   const StripBins* strips) {
  const long nn = grid.nodes();
  const std::size_t nb = bodies.size();
  std::vector<Vec<D>> vb(nb);
  std::vector<double> face(nb);
  // each body's presence array, looked up once
  std::vector<const double*> presence(nb);
  for (std::size_t b = 0; b < nb; ++b) {
    vb[b] = bodies[b].velocity_at(t);
    face[b] = bodies[b].face_at(t) + 1e-9 * grid.h;
    presence[b] = grid.presence.data() +
                  static_cast<std::size_t>(bodies[b].field - grid.deformable) * static_cast<std::size_t>(nn);
  }

  const StripBins bins_of_grid = strips ? StripBins{} : StripBins::of_grid(grid);
  const StripBins& bins = strips ? *strips : bins_of_grid;
  // the body nodes of each strip, ascending: a strip's nodes in node order
  std::vector<std::vector<long>> by_strip(static_cast<std::size_t>(bins.strips));
  for (const long i : body_nodes) by_strip[static_cast<std::size_t>(bins.strip_of_cell(i % grid.n[0]))].push_back(i);

  auto pass = [&](long strip, BodySums<D>& s) {
    for (const long i : by_strip[static_cast<std::size_t>(strip)]) {
      for (std::size_t b = 0; b < nb; ++b) {
        if (presence[b][i] <= 0.0) continue;
        const Vec<D>& n = bodies[b].normal;
        const double xn = grid.position(i).dot(n);
        const bool behind = xn <= face[b];
        const double reach = bodies[b].cutoff * grid.h;
        for (int f = 0; f < deformable; ++f) {
          const long k = grid.at(f, i);
          const double m = grid.mass[k];
          if (m <= mass_eps) continue;
          if (!behind && (grid.origin + grid.moff[k] / m).dot(n) - face[b] > reach) continue;
          const Vec<D> vrel = grid.mom[k] / m - vb[b];
          // the body is the infinite-mass limit of the field laws: a stick body welds, a
          // unilateral one is Coulomb with its friction (frictionless at 0)
          const RigidExchange<D> e = bodies[b].contact == RigidContact::stick
                                         ? WeldLaw{}.rigid<D>(m, vrel)
                                         : CoulombLaw{bodies[b].friction, 0.0}.rigid<D>(m, vrel, n);
          if (!e.acts) continue;
          const Vec<D>& dp = e.dp;
          const double fw = e.friction_work;
          grid.mom[k] += dp;
          s.impulse[b] += dp;
          s.work[b] += dp.dot(vb[b]);
          s.friction[b] += fw;
        }
      }
    }
  };
  bins.fold_then(BodySums<D>(nb), pass, [book](const BodySums<D>& sums) {
    if (book) book(RigidContactResult<D>{sums.impulse, sums.work, sums.friction});
  });
}

template void rigid_contact<2>(Grid<2>&, std::vector<RigidBody<2>>&, int, double, double, const std::vector<long>&,
                               const std::function<void(const RigidContactResult<2>&)>&, const StripBins*);
template void rigid_contact<3>(Grid<3>&, std::vector<RigidBody<3>>&, int, double, double, const std::vector<long>&,
                               const std::function<void(const RigidContactResult<3>&)>&, const StripBins*);

}  // namespace pbx
