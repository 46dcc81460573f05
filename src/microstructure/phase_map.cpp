#include "microstructure/phase_map.hpp"

#include <algorithm>
#include <cmath>

namespace pbx {

PhaseMap::PhaseMap(const Packing& p) : p_(p) {
  if (p.image.nx > 0) return;
  disks_ = disks_in_box(p, true);
  double rmax = 0;
  for (const auto& d : disks_) rmax = std::max(rmax, d.radius);
  // Buckets about a fine grain across: few disks per bucket, few buckets per disk.
  bucket_ = std::max(p.box.maxCoeff() / 256.0, 0.25 * rmax);
  nx_ = std::max(1, static_cast<int>(std::ceil(p.box.x() / bucket_)));
  ny_ = std::max(1, static_cast<int>(std::ceil(p.box.y() / bucket_)));
  buckets_.assign(static_cast<std::size_t>(nx_) * ny_, {});
  for (int k = 0; k < static_cast<int>(disks_.size()); ++k) {
    const auto& d = disks_[k];
    const int i0 = std::clamp(static_cast<int>(std::floor((d.centre.x() - d.radius) / bucket_)), 0, nx_ - 1);
    const int i1 = std::clamp(static_cast<int>(std::floor((d.centre.x() + d.radius) / bucket_)), 0, nx_ - 1);
    const int j0 = std::clamp(static_cast<int>(std::floor((d.centre.y() - d.radius) / bucket_)), 0, ny_ - 1);
    const int j1 = std::clamp(static_cast<int>(std::floor((d.centre.y() + d.radius) / bucket_)), 0, ny_ - 1);
    for (int j = j0; j <= j1; ++j)
      for (int i = i0; i <= i1; ++i) buckets_[static_cast<std::size_t>(j) * nx_ + i].push_back(k);
  }
}

PhaseHit PhaseMap::at(const Eigen::Vector2d& x) const {
  if (!(x.x() >= 0 && x.x() < p_.box.x() && x.y() >= 0 && x.y() < p_.box.y())) return {};
  if (p_.image.nx > 0) {
    const auto& im = p_.image;
    const int i = std::min(im.nx - 1, static_cast<int>(x.x() / im.pixel));
    const int j = std::min(im.ny - 1, static_cast<int>(x.y() / im.pixel));
    const int l = im.label[static_cast<std::size_t>(j) * im.nx + i];
    if (l >= 0) return {MesoPhase::tatb, l};
    return {l == -1 ? MesoPhase::binder : MesoPhase::void_, -1};
  }
  const int i = std::min(nx_ - 1, static_cast<int>(x.x() / bucket_));
  const int j = std::min(ny_ - 1, static_cast<int>(x.y() / bucket_));
  PhaseHit hit;
  for (int k : buckets_[static_cast<std::size_t>(j) * nx_ + i]) {
    const Disk& d = disks_[k];
    const double r2 = (x - d.centre).squaredNorm();
    if (r2 >= d.radius * d.radius) continue;
    const double core = 0.5 * p_.grains[d.grain].diameter;
    if (r2 < core * core) return {MesoPhase::tatb, d.grain};
    hit.phase = MesoPhase::binder;
  }
  return hit;
}

}  // namespace pbx
