#pragma once
// Dense random packing of disks of given radii in a rectangle (periodic or walled): soft-disk
// energy minimisation (FIRE, Bitzek et al. 2006) driving growth of the coarse disks from random
// positions (Lubachevsky & Stillinger 1990 style compression, force-biased overlap removal in the
// family of Jodrey & Tory 1985 / Moscinski et al. 1989), then the fine disks, largest first, put
// into the largest empty circles of the packing and relaxed with everything else, then relocation
// of the most squeezed fine disks into the largest voids. See docs/theory/microstructure.md.
#include <vector>

#include <Eigen/Dense>

#include "microstructure/rng.hpp"

namespace pbx {

struct DiskPackerOptions {
  bool periodic = false;          // periodic box (no walls): the box is a window into a bulk packing
  double start_scale = 0.5;       // random disks start at this fraction of their size and grow
  int growth_steps = 10;          // growth steps of the random disks (each relaxed)
  int batch = 1;                  // void-filling disks inserted between two relaxations
  int relocations = 40;           // squeezed void-filling disks moved to the largest void, at most
  int max_iterations = 5000;      // FIRE iterations per relaxation
  int final_iterations = 100000;  // FIRE iterations of the last relaxation
};

struct DiskPackerResult {
  std::vector<Eigen::Vector2d> centres;
  bool overlap_free = false;  // every pair and every wall satisfied exactly
  double max_overlap = 0;     // m, largest remaining pair or wall overlap
  double fit_scale = 0;       // largest factor (<= 1) all radii could take without any overlap
  int relocations = 0;        // relocation moves done
  int iterations = 0;         // FIRE iterations in total
};

// radius[i]: disk radius for disk-disk contacts; wall_radius[i] >= radius[i]: distance the centre
// keeps from the walls (room for the binder coat; unused when periodic). Disks with
// into_voids[i] == false are placed at random (uniformly) and grown first; the others are then put
// into the largest voids in order of decreasing radius (ties: index order).
DiskPackerResult pack_disks(const std::vector<double>& radius, const std::vector<double>& wall_radius,
                            const std::vector<bool>& into_voids, const Eigen::Vector2d& box, Rng& rng,
                            const DiskPackerOptions& opt = {});

}  // namespace pbx
