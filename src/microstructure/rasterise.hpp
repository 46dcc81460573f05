#pragma once
// Packing -> MPM particles. Each grid cell is split into ppc x ppc square sub-cells; a particle sits
// at the centre of every sub-cell whose centre lies in a solid phase and takes that phase (centre
// sampling: an unbiased estimate of every phase's area, see docs/theory/microstructure.md). Voids
// get no particle. Output order: cells row-major (y outer, x inner), then sub-cells likewise.
#include <vector>

#include <Eigen/Dense>

#include "microstructure/packing.hpp"

namespace pbx {

struct ParticleSeed {
  Eigen::Vector2d x;  // m, in the MPM grid frame (origin + position in the box)
  double volume;      // m^2 per metre of depth (plane strain): the sub-cell area
  int phase;          // 0 = TATB grain, 1 = binder
  int grain;          // grain index in Packing::grains, -1 for binder
  int colour;         // grain colour (contact field), -1 for binder
};

// origin: where the lower-left corner of the packing box sits in the MPM grid; the grid's cells
// are assumed to start there (cell i spans origin.x + [i, i+1) * cell_size).
std::vector<ParticleSeed> rasterise(const Packing& p, double cell_size, int particles_per_cell_per_axis,
                                    Eigen::Vector2d origin);

// The resolution at which the particle set matches the geometry to 0.5 % (mass ratio and porosity):
// cell = 2 um with 2 x 2 particles per cell (1 um sub-cells). Verified in tests/microstructure.
inline constexpr double kDefaultCellSize = 2e-6;
inline constexpr int kDefaultParticlesPerAxis = 2;

struct RasterReport {
  std::size_t particles = 0, tatb_particles = 0, binder_particles = 0;
  double tatb_mass_fraction = 0;   // of the solids
  double tatb_to_binder_mass = 0;  // mass ratio TATB / binder
  double porosity = 0;             // 1 - particle area / box area
};

// Mass ratio and porosity of a particle set, for given phase densities (they may differ from the
// packing's when the run temperature expands the phases).
RasterReport raster_report(const std::vector<ParticleSeed>& particles, const Eigen::Vector2d& box, double tatb_density,
                           double binder_density);

}  // namespace pbx
