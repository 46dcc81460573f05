#include "microstructure/rasterise.hpp"

#include <cmath>

#include <fmt/format.h>

#include "core/error.hpp"
#include "microstructure/phase_map.hpp"

namespace pbx {

std::vector<ParticleSeed> rasterise(const Packing& p, double cell_size, int ppc, Eigen::Vector2d origin) {
  if (!(cell_size > 0)) throw InputError(fmt::format("rasterise: cell size must be > 0 (got {} m)", cell_size));
  if (ppc < 1) throw InputError(fmt::format("rasterise: particles per cell per axis must be >= 1 (got {})", ppc));
  const PhaseMap map(p);
  const int ncx = static_cast<int>(std::ceil(p.box.x() / cell_size - 1e-9));
  const int ncy = static_cast<int>(std::ceil(p.box.y() / cell_size - 1e-9));
  const double h = cell_size / ppc;
  std::vector<ParticleSeed> out;
  for (int cj = 0; cj < ncy; ++cj)
    for (int ci = 0; ci < ncx; ++ci)
      for (int sj = 0; sj < ppc; ++sj)
        for (int si = 0; si < ppc; ++si) {
          const Eigen::Vector2d x{ci * cell_size + (si + 0.5) * h, cj * cell_size + (sj + 0.5) * h};
          const PhaseHit hit = map.at(x);
          if (hit.phase == MesoPhase::void_) continue;
          const bool tatb = hit.phase == MesoPhase::tatb;
          out.push_back(
              {origin + x, h * h, tatb ? 0 : 1, tatb ? hit.grain : -1, tatb ? p.grains[hit.grain].colour : -1});
        }
  return out;
}

RasterReport raster_report(const std::vector<ParticleSeed>& particles, const Eigen::Vector2d& box, double tatb_density,
                           double binder_density) {
  RasterReport r;
  double vt = 0, vb = 0;
  for (const auto& s : particles) {
    (s.phase == 0 ? vt : vb) += s.volume;
    (s.phase == 0 ? r.tatb_particles : r.binder_particles) += 1;
  }
  r.particles = particles.size();
  const double mt = vt * tatb_density, mb = vb * binder_density;
  r.tatb_mass_fraction = mt / (mt + mb);
  r.tatb_to_binder_mass = mb > 0 ? mt / mb : INFINITY;
  r.porosity = 1.0 - (vt + vb) / box.prod();
  return r;
}

}  // namespace pbx
