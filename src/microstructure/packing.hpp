#pragma once
// A mesostructure: binder-coated TATB disks in a rectangular box. Generated from a [packing] deck
// table (bimodal sizes, exact TATB:binder mass ratio, target porosity) or imported from a
// segmented image; written as packing.csv + packing.json + packing.png. See
// docs/theory/microstructure.md for the algorithm and docs/deck/microstructure.md for the keys.
#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include <Eigen/Dense>

#include "microstructure/size_distribution.hpp"

namespace pbx {

class DeckTable;

struct Grain {
  Eigen::Vector2d centre;  // m; inside [0, box) (periodic packings) or the box minus the radius
  double diameter = 0;     // m, TATB disk
  double coat = 0;         // m, binder coat thickness (coats may overlap: binder bridges)
  int colour = 0;          // contact colour: grains whose coats come within contact_gap differ
  int mode = 0;            // size mode it was drawn from (0 coarse, 1 fine; -1 imported)
};

// Segmented picture (image import): the phase of every pixel, row 0 at the bottom of the box.
struct PhaseImage {
  int nx = 0, ny = 0;
  double pixel = 0;        // m, square pixels
  std::vector<int> label;  // nx*ny, row-major from the bottom: -2 void, -1 binder, >= 0 grain
};

struct PackingStats {
  double porosity = 0;                // void area / box area
  double density = 0;                 // kg/m3, mean over the box (voids empty)
  double tmd = 0;                     // kg/m3, theoretical maximum density (no voids)
  double tatb_area_fraction = 0;      // of the box
  double binder_area_fraction = 0;    // of the box
  double tatb_mass_fraction = 0;      // of the solids
  double coat_min = 0, coat_max = 0;  // m
  int colours = 0;
  int grains_coarse = 0, grains_fine = 0;
};

struct Packing {
  Eigen::Vector2d box{0, 0};  // m, width x height; origin at the lower-left corner
  bool periodic = true;       // grains cut by an edge reappear at the opposite edge
  std::vector<Grain> grains;
  std::uint64_t seed = 0;
  double tatb_density = 0, binder_density = 0;  // kg/m3, of the phases used for the arithmetic
  double contact_gap = 0;                       // m, used for the colouring
  std::string source = "generated";             // or the imported image's file name
  PhaseImage image;                             // only for imported packings (nx > 0)
  int grains_shrunk = 0;                        // grains reduced to remove the last overlaps
  double max_shrink = 0;                        // largest relative diameter reduction (<= 1 %)
  int attempt = 0;                              // placement that succeeded (1-based; 0 imported)
  std::array<int, 2> tiles{1, 1};               // copies of the packed cell along x and y (see tile_packing)
  PackingStats stats;                           // measured on the geometry, see measure()
};

struct PackingSpec {
  Eigen::Vector2d box{1.0e-3, 1.2e-3};
  SizeDistribution sizes;
  double tatb_mass = 95, binder_mass = 5;             // TATB:binder mass ratio (parts)
  double tatb_density = 1934, binder_density = 2020;  // kg/m3
  double porosity = 0.08;                             // target (a deck `density` is converted to this)
  double tolerance = 0.002;                           // allowed |achieved - target| porosity
  std::uint64_t seed = 1;
  bool uniform_coat = false;  // uniform thickness, else proportional to diameter
  double contact_gap = 2e-6;  // m
  bool periodic = true;
  int attempts = 8;  // packings tried (different placements) before failing
  // Copies of the packed box along x and y: the specimen is `tiles` periods of one periodic
  // packing (box × tiles), e.g. the same work per rank in a weak-scaling run.
  std::array<int, 2> tiles{1, 1};

  // Theoretical maximum density from the phase densities and the mass ratio.
  double tmd() const;
  // Binder area per TATB area for the mass ratio: (m_b/m_T)(rho_T/rho_b).
  double binder_per_tatb_area() const;
};

// Reads a [packing] table (the same keys in a pack deck and a run deck).
PackingSpec read_packing_spec(const DeckTable& t);

// Throws InputError when the target porosity cannot be reached, stating the best reached.
Packing generate_packing(const PackingSpec& spec);

// `tiles` periods of a periodic packing side by side: every grain repeated at each offset
// (i box_x, j box_y), colours kept (they separate the periodic images' contacts already, so they
// separate the copies'), the box tiles × box. Throws InputError for a packing with walls or one
// imported from an image.
Packing tile_packing(const Packing& cell, std::array<int, 2> tiles);

// Recomputes p.stats from the geometry (exact circle-union areas, or pixel counts for images).
void measure(Packing& p);

// Circles as they appear in the box: every grain once, plus its periodic images that reach into
// the box. coated = true gives the coat's outer circle.
struct Disk {
  Eigen::Vector2d centre;
  double radius;
  int grain;
};
std::vector<Disk> disks_in_box(const Packing& p, bool coated);

void write_packing(const Packing& p, const std::string& dir);  // packing.csv, .json, .png
Packing read_packing(const std::string& dir);

}  // namespace pbx
