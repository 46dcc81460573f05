#pragma once
// Dense random packing of disks of given radii in a walled rectangle by growth with overlap
// removal (a force-biased algorithm in the family of Jodrey & Tory 1985 and Moscinski et al. 1989,
// driven like Lubachevsky & Stillinger 1990: all radii grow together from a fraction of their size,
// and after each growth step overlaps are removed by Gauss-Seidel projections that move the
// smaller disk of a pair more). See docs/theory/microstructure.md.
#include <vector>

#include <Eigen/Dense>

#include "microstructure/rng.hpp"

namespace pbx {

struct DiskPackerOptions {
  double start_scale = 0.55;   // radii start at this fraction of their final size
  int growth_steps = 400;      // scale steps from start_scale to 1 (geometric)
  int sweeps_per_step = 60;    // projection sweeps allowed per step before it counts as jammed
  int final_sweeps = 20000;    // sweeps allowed at full size to remove the last overlaps
  bool periodic = false;       // periodic box (no walls): the box is a window into a bulk packing
  int candidates = 1;          // random points tried per disk; the one with most clearance wins
};

struct DiskPackerResult {
  std::vector<Eigen::Vector2d> centres;
  bool overlap_free = false;  // every pair and every wall satisfied exactly
  double max_overlap = 0;     // m, largest remaining pair or wall overlap
  int sweeps = 0;             // projection sweeps done in total
};

// radius[i]: disk radius for disk-disk contacts; wall_radius[i] >= radius[i]: distance the centre
// keeps from the walls (room for the binder coat). Disks are placed at random (uniformly inside the
// walls) in the order given.
// Disks grow in stages: stage[i] = 0 first; the disks of stage k are placed and grown while those
// of earlier stages are at full size (and still move).
DiskPackerResult pack_disks(const std::vector<double>& radius, const std::vector<double>& wall_radius,
                            const std::vector<int>& stage, const Eigen::Vector2d& box, Rng& rng,
                            const DiskPackerOptions& opt = {});

}  // namespace pbx
