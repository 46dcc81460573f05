#pragma once
// Point query "which phase is at x" for a packing: TATB inside a grain's disk, binder inside a coat
// (and outside every grain), void elsewhere; imported packings answer from their pixels. A bucket
// grid over the box keeps a query to the few disks near x.
#include <vector>

#include <Eigen/Dense>

#include "microstructure/packing.hpp"

namespace pbx {

enum class MesoPhase { tatb = 0, binder = 1, void_ = 2 };

struct PhaseHit {
  MesoPhase phase = MesoPhase::void_;
  int grain = -1;  // grain index for TATB, -1 otherwise
};

class PhaseMap {
 public:
  explicit PhaseMap(const Packing& p);
  // x in box coordinates (origin at the lower-left corner); outside the box: void.
  PhaseHit at(const Eigen::Vector2d& x) const;

 private:
  const Packing& p_;
  std::vector<Disk> disks_;  // coated circles in the box, with images
  double bucket_ = 1;
  int nx_ = 0, ny_ = 0;
  std::vector<std::vector<int>> buckets_;  // disk indices overlapping each bucket
};

}  // namespace pbx
