#include "microstructure/disk_packer.hpp"

#include <algorithm>
#include <cmath>

namespace pbx {

namespace {

struct Packer {
  const std::vector<double>& r;
  const std::vector<double>& rw;
  Eigen::Vector2d box;
  std::vector<Eigen::Vector2d> x;
  std::vector<Eigen::Vector2d> x_at_build;
  std::vector<std::pair<int, int>> pairs;
  double skin = 0;
  std::vector<double> scale;  // per disk: growing disks are below 1
  int sweeps = 0;
  bool periodic = false;

  // Separation vector from a to b; with periodic boundaries the nearest image of b.
  Eigen::Vector2d sep(const Eigen::Vector2d& a, const Eigen::Vector2d& b) const {
    Eigen::Vector2d d = b - a;
    if (periodic)
      for (int k = 0; k < 2; ++k) d[k] -= box[k] * std::round(d[k] / box[k]);
    return d;
  }

  void build_pairs() {
    pairs.clear();
    const int n = static_cast<int>(x.size());
    for (int i = 0; i < n; ++i)
      for (int j = i + 1; j < n; ++j) {
        const double reach = scale[i] * r[i] + scale[j] * r[j] + skin;
        if (sep(x[i], x[j]).squaredNorm() < reach * reach) pairs.emplace_back(i, j);
      }
    x_at_build = x;
  }

  void maybe_rebuild() {
    double worst = 0;
    for (std::size_t i = 0; i < x.size(); ++i) worst = std::max(worst, sep(x_at_build[i], x[i]).squaredNorm());
    if (4.0 * worst > skin * skin) build_pairs();
  }

  // Moves every overlapping pair apart to `target` = scale (r_i + r_j) (1 + margin), sharing the
  // move in inverse proportion to the disks' areas, then projects into the walls. Returns the
  // largest overlap seen before the moves (relative to the exact contact distance).
  double sweep(double margin) {
    ++sweeps;
    double worst = 0;
    for (auto [i, j] : pairs) {
      Eigen::Vector2d d = sep(x[i], x[j]);
      const double dist = d.norm();
      const double contact = scale[i] * r[i] + scale[j] * r[j];
      worst = std::max(worst, contact - dist);
      const double target = contact * (1.0 + margin);
      if (dist >= target) continue;
      // Coincident centres cannot happen after random placement but would give no direction.
      const Eigen::Vector2d n = dist > 0 ? Eigen::Vector2d(d / dist) : Eigen::Vector2d(1, 0);
      const double ai = r[i] * r[i], aj = r[j] * r[j];
      const double push = target - dist;
      x[i] -= n * (push * aj / (ai + aj));
      x[j] += n * (push * ai / (ai + aj));
    }
    for (std::size_t i = 0; i < x.size(); ++i) {
      if (periodic) {
        for (int a = 0; a < 2; ++a) x[i][a] -= box[a] * std::floor(x[i][a] / box[a]);
        continue;
      }
      const double w = scale[i] * rw[i];
      for (int a = 0; a < 2; ++a) {
        worst = std::max({worst, w - x[i][a], x[i][a] - (box[a] - w)});
        x[i][a] = std::clamp(x[i][a], w, box[a] - w);
      }
    }
    maybe_rebuild();
    return worst;
  }
};

}  // namespace

DiskPackerResult pack_disks(const std::vector<double>& radius, const std::vector<double>& wall_radius,
                            const std::vector<int>& stage, const Eigen::Vector2d& box, Rng& rng,
                            const DiskPackerOptions& opt) {
  const std::size_t n = radius.size();
  Packer p{radius, wall_radius, box, {}, {}, {}, 0, std::vector<double>(n, 0.0), 0};
  const double rmin = *std::min_element(radius.begin(), radius.end());
  p.skin = 0.5 * rmin;
  p.periodic = opt.periodic;
  p.x.assign(n, Eigen::Vector2d::Zero());
  const int stages = n ? *std::max_element(stage.begin(), stage.end()) + 1 : 0;
  // Relative tolerance of "overlap removed" while growing; the last stage removes all of it.
  const double tol = 1e-4 * rmin;
  const double growth = std::pow(1.0 / opt.start_scale, 1.0 / opt.growth_steps);
  for (int st = 0; st < stages; ++st) {
    // Each new disk goes to the best of a few random points: the one farthest from the surfaces
    // already there, so later (smaller) disks start inside the voids of the earlier ones.
    std::vector<std::size_t> group;
    for (std::size_t i = 0; i < n; ++i)
      if (stage[i] == st) group.push_back(i);
    for (std::size_t i : group) {
      double best = -1e300;
      Eigen::Vector2d best_x = Eigen::Vector2d::Zero();
      for (int c = 0; c < opt.candidates; ++c) {
        Eigen::Vector2d y;
        for (int a = 0; a < 2; ++a) y[a] = rng.uniform(wall_radius[i], box[a] - wall_radius[i]);
        double clearance = 1e300;
        for (std::size_t j = 0; j < n; ++j)
          if (p.scale[j] > 0) clearance = std::min(clearance, p.sep(y, p.x[j]).norm() - p.scale[j] * radius[j]);
        if (clearance > best) best = clearance, best_x = y;
      }
      p.x[i] = best_x;
      p.scale[i] = opt.start_scale;
    }
    p.build_pairs();
    for (int s = 0; s < opt.growth_steps; ++s) {
      for (std::size_t i : group) p.scale[i] = std::min(1.0, p.scale[i] * growth);
      p.build_pairs();
      for (int k = 0; k < opt.sweeps_per_step; ++k)
        if (p.sweep(1e-3) < tol) break;
    }
    for (std::size_t i : group) p.scale[i] = 1.0;
  }
  p.build_pairs();
  DiskPackerResult res;
  // A small separation margin lets the last sweeps end with strictly positive gaps.
  for (int k = 0; k < opt.final_sweeps; ++k) {
    p.sweep(1e-6);
    double worst = 0;
    for (auto [i, j] : p.pairs) worst = std::max(worst, radius[i] + radius[j] - p.sep(p.x[i], p.x[j]).norm());
    if (worst <= 0) {
      res.overlap_free = true;
      break;
    }
    res.max_overlap = worst;
  }
  if (res.overlap_free) {
    // The pair list may miss no pair (skin), but check against all pairs to be certain.
    res.max_overlap = 0;
    for (std::size_t i = 0; i < p.x.size(); ++i)
      for (std::size_t j = i + 1; j < p.x.size(); ++j)
        res.max_overlap = std::max(res.max_overlap, radius[i] + radius[j] - p.sep(p.x[i], p.x[j]).norm());
    res.overlap_free = res.max_overlap <= 0;
    res.max_overlap = std::max(0.0, res.max_overlap);
  }
  res.centres = std::move(p.x);
  res.sweeps = p.sweeps;
  return res;
}

}  // namespace pbx
