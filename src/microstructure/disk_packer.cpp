#include "microstructure/disk_packer.hpp"

#include <algorithm>
#include <cmath>

namespace pbx {

namespace {

// Soft disks: a pair (or a disk and a wall) that overlaps by o stores the energy o^2/2 and pushes
// with the force o along the centre line. Unit masses and stiffnesses make the FIRE time step
// independent of the length unit.
struct Packer {
  Packer(const std::vector<double>& radius, const std::vector<double>& wall_radius, const Eigen::Vector2d& b, bool p)
      : r(radius), rw(wall_radius), box(b), periodic(p) {}

  const std::vector<double>& r;
  const std::vector<double>& rw;
  Eigen::Vector2d box;
  bool periodic = false;
  std::vector<Eigen::Vector2d> x, v, f, x_at_build;
  std::vector<char> active;  // disks in the box (void-filling disks arrive later)
  double s = 1;              // radius factor of all disks (growth, final margin)
  std::vector<std::pair<int, int>> pairs;
  double skin = 0;
  int iterations = 0;

  int size() const { return static_cast<int>(x.size()); }

  // Separation vector from a to b; with periodic boundaries the nearest image of b.
  Eigen::Vector2d sep(const Eigen::Vector2d& a, const Eigen::Vector2d& b) const {
    Eigen::Vector2d d = b - a;
    if (periodic)
      for (int k = 0; k < 2; ++k) d[k] -= box[k] * std::round(d[k] / box[k]);
    return d;
  }

  void wrap(Eigen::Vector2d& y) const {
    if (periodic)
      for (int k = 0; k < 2; ++k) y[k] -= box[k] * std::floor(y[k] / box[k]);
  }

  void build_pairs() {
    pairs.clear();
    for (int i = 0; i < size(); ++i) {
      if (!active[i]) continue;
      for (int j = i + 1; j < size(); ++j) {
        if (!active[j]) continue;
        const double reach = s * (r[i] + r[j]) + skin;
        if (sep(x[i], x[j]).squaredNorm() < reach * reach) pairs.emplace_back(i, j);
      }
    }
    x_at_build = x;
  }

  void maybe_rebuild() {
    double worst = 0;
    for (int i = 0; i < size(); ++i)
      if (active[i]) worst = std::max(worst, sep(x_at_build[i], x[i]).squaredNorm());
    if (4.0 * worst > skin * skin) build_pairs();
  }

  double forces() {
    for (auto& fi : f) fi.setZero();
    double energy = 0;
    for (auto [i, j] : pairs) {
      const Eigen::Vector2d d = sep(x[i], x[j]);
      const double contact = s * (r[i] + r[j]);
      const double dist2 = d.squaredNorm();
      if (dist2 >= contact * contact) continue;
      const double dist = std::sqrt(dist2);
      const double o = contact - dist;
      energy += 0.5 * o * o;
      // Coincident centres cannot survive random placement but would give no direction.
      const Eigen::Vector2d n = dist > 0 ? Eigen::Vector2d(d / dist) : Eigen::Vector2d(1, 0);
      f[i] -= o * n;
      f[j] += o * n;
    }
    if (!periodic)
      for (int i = 0; i < size(); ++i) {
        if (!active[i]) continue;
        const double w = s * rw[i];
        for (int k = 0; k < 2; ++k) {
          const double lo = w - x[i][k], hi = x[i][k] - (box[k] - w);
          if (lo > 0) f[i][k] += lo, energy += 0.5 * lo * lo;
          if (hi > 0) f[i][k] -= hi, energy += 0.5 * hi * hi;
        }
      }
    return energy;
  }

  // FIRE minimisation of the overlap energy (Bitzek, Koskinen, Gaehler, Moseler & Gumbsch 2006,
  // their recommended parameters) until no force component sum exceeds ftol. Returns the energy.
  double relax(int max_iterations, double ftol) {
    const int n = size();
    v.assign(n, Eigen::Vector2d::Zero());
    double dt = 0.1, alpha = 0.1;
    const double dt_max = 0.5;
    int positive = 0;
    maybe_rebuild();
    double energy = forces();
    for (int it = 0; it < max_iterations; ++it) {
      double power = 0, fnorm = 0, vnorm = 0, fmax = 0;
      for (int i = 0; i < n; ++i) {
        if (!active[i]) continue;
        power += f[i].dot(v[i]);
        fnorm += f[i].squaredNorm();
        vnorm += v[i].squaredNorm();
        fmax = std::max(fmax, f[i].cwiseAbs().sum());
      }
      if (fmax < ftol) break;
      fnorm = std::sqrt(fnorm);
      vnorm = std::sqrt(vnorm);
      if (power > 0) {
        for (int i = 0; i < n; ++i) v[i] = (1 - alpha) * v[i] + alpha * vnorm * f[i] / fnorm;
        if (++positive > 5) dt = std::min(1.1 * dt, dt_max), alpha *= 0.99;
      } else {
        positive = 0;
        dt *= 0.5;
        alpha = 0.1;
        for (auto& vi : v) vi.setZero();
      }
      for (int i = 0; i < n; ++i) {
        if (!active[i]) continue;
        v[i] += dt * f[i];
        x[i] += dt * v[i];
        wrap(x[i]);
      }
      ++iterations;
      maybe_rebuild();
      energy = forces();
    }
    return energy;
  }

  // Distance from y to the nearest disk surface (and wall), ignoring disk `skip`.
  double clearance(const Eigen::Vector2d& y, int skip) const {
    double c = 1e300;
    if (!periodic)
      for (int k = 0; k < 2; ++k) c = std::min({c, y[k], box[k] - y[k]});
    for (int j = 0; j < size(); ++j)
      if (active[j] && j != skip) c = std::min(c, sep(y, x[j]).norm() - s * r[j]);
    return c;
  }

  // Clearance at the nodes of a regular grid (cell h), the seed of the largest-empty-circle search.
  struct VoidGrid {
    int nx = 0, ny = 0;
    double h = 0;
    std::vector<double> c;
    Eigen::Vector2d node(int k) const { return {(k / ny + 0.5) * h, (k % ny + 0.5) * h}; }
  };

  void fill_grid(VoidGrid& g, int skip) const {
    for (int k = 0; k < g.nx * g.ny; ++k) g.c[k] = clearance(g.node(k), skip);
  }

  // Largest empty circle: the best grid node, refined by a compass search on the clearance.
  // Returns its centre; `c` receives its radius.
  Eigen::Vector2d largest_void(const VoidGrid& g, int skip, double& c) const {
    const int k = static_cast<int>(std::max_element(g.c.begin(), g.c.end()) - g.c.begin());
    Eigen::Vector2d y = g.node(k);
    c = g.c[k];
    for (double step = 0.5 * g.h; step > 1e-3 * g.h; step *= 0.5)
      for (bool moved = true; moved;) {
        moved = false;
        for (int q = 0; q < 8; ++q) {
          const double a = q * (2 * 3.14159265358979323846 / 8);
          Eigen::Vector2d z = y + step * Eigen::Vector2d(std::cos(a), std::sin(a));
          if (!periodic) z = z.cwiseMax(0.0).cwiseMin(box);
          const double cz = clearance(z, skip);
          if (cz > c) c = cz, y = z, moved = true;
        }
      }
    wrap(y);
    return y;
  }

  // Largest pair or wall overlap at the current radius factor.
  double max_overlap(bool all_pairs) const {
    double worst = 0;
    if (all_pairs) {
      for (int i = 0; i < size(); ++i)
        for (int j = i + 1; j < size(); ++j) worst = std::max(worst, s * (r[i] + r[j]) - sep(x[i], x[j]).norm());
    } else {
      for (auto [i, j] : pairs) worst = std::max(worst, s * (r[i] + r[j]) - sep(x[i], x[j]).norm());
    }
    if (!periodic)
      for (int i = 0; i < size(); ++i)
        for (int k = 0; k < 2; ++k) worst = std::max({worst, s * rw[i] - x[i][k], x[i][k] - (box[k] - s * rw[i])});
    return worst;
  }

  // Largest common factor of all radii (at most 1) that leaves no overlap.
  double fit_scale() const {
    double fit = 1;
    for (int i = 0; i < size(); ++i) {
      for (int j = i + 1; j < size(); ++j) fit = std::min(fit, sep(x[i], x[j]).norm() / (r[i] + r[j]));
      if (!periodic)
        for (int k = 0; k < 2; ++k) fit = std::min({fit, x[i][k] / rw[i], (box[k] - x[i][k]) / rw[i]});
    }
    return std::max(fit, 0.0);
  }

  // Per-disk sum of pair overlaps (the squeeze a void-filling disk is under).
  std::vector<double> squeeze() const {
    std::vector<double> out(size(), 0.0);
    for (auto [i, j] : pairs) {
      const double o = s * (r[i] + r[j]) - sep(x[i], x[j]).norm();
      if (o > 0) out[i] += o, out[j] += o;
    }
    return out;
  }
};

}  // namespace

DiskPackerResult pack_disks(const std::vector<double>& radius, const std::vector<double>& wall_radius,
                            const std::vector<bool>& into_voids, const Eigen::Vector2d& box, Rng& rng,
                            const DiskPackerOptions& opt) {
  const int n = static_cast<int>(radius.size());
  DiskPackerResult res;
  if (n == 0) return res;
  Packer p(radius, wall_radius, box, opt.periodic);
  p.x.assign(n, Eigen::Vector2d::Zero());
  p.f.assign(n, Eigen::Vector2d::Zero());
  p.active.assign(n, 0);
  const double rmin = *std::min_element(radius.begin(), radius.end());
  p.skin = 0.3 * rmin;
  // Force tolerances: relaxations stop when every disk's net push is below these (m).
  const double ftol = 4e-8 * rmin, ftol_final = 4e-12 * rmin;

  std::vector<int> random, voids;
  for (int i = 0; i < n; ++i) (into_voids[i] ? voids : random).push_back(i);
  if (random.empty()) std::swap(random, voids);  // nothing to fill the voids of: all at random
  std::stable_sort(voids.begin(), voids.end(), [&](int a, int b) { return radius[a] > radius[b]; });

  // 1. Random disks: uniform positions, grown from start_scale to full size, relaxed at each step.
  for (int i : random) {
    for (int k = 0; k < 2; ++k)
      p.x[i][k] = opt.periodic ? rng.uniform(0.0, box[k]) : rng.uniform(wall_radius[i], box[k] - wall_radius[i]);
    p.active[i] = 1;
  }
  for (int step = 0; step <= opt.growth_steps; ++step) {
    p.s = opt.start_scale + (1.0 - opt.start_scale) * step / std::max(1, opt.growth_steps);
    p.build_pairs();
    p.relax(4 * opt.max_iterations, ftol);
  }
  p.s = 1;

  // 2. Void-filling disks, largest first, each at the centre of the largest empty circle; after a
  //    batch (or when the voids left are much smaller than the next disk) everything relaxes.
  Packer::VoidGrid grid;
  grid.h = std::max(0.4 * (voids.empty() ? rmin : radius[voids.back()]), std::sqrt(box.prod() / 40000.0));
  grid.nx = std::max(1, static_cast<int>(box.x() / grid.h));
  grid.ny = std::max(1, static_cast<int>(box.y() / grid.h));
  grid.h = std::min(box.x() / grid.nx, box.y() / grid.ny);
  grid.c.assign(static_cast<std::size_t>(grid.nx) * grid.ny, 0.0);
  for (std::size_t next = 0; next < voids.size();) {
    p.fill_grid(grid, -1);
    for (int in_batch = 0; next < voids.size() && in_batch < opt.batch; ++in_batch) {
      const int i = voids[next];
      double c = 0;
      const Eigen::Vector2d y = p.largest_void(grid, -1, c);
      if (in_batch > 0 && c < 0.6 * radius[i]) break;
      p.x[i] = y;
      p.active[i] = 1;
      ++next;
      for (int k = 0; k < grid.nx * grid.ny; ++k)
        grid.c[k] = std::min(grid.c[k], p.sep(grid.node(k), y).norm() - radius[i]);
    }
    p.build_pairs();
    p.relax(opt.max_iterations, ftol);
  }
  p.build_pairs();
  p.relax(4 * opt.max_iterations, ftol);

  // 3. While squeezed: the void-filling disk under the largest squeeze leaves, the rest relaxes,
  //    and it comes back at the centre of the largest empty circle. The best state is kept.
  std::vector<Eigen::Vector2d> best_x = p.x;
  double best_fit = p.fit_scale();
  const double squeezed = 1e-6 * rmin;
  for (int move = 0; move < opt.relocations && !voids.empty() && p.max_overlap(false) > squeezed; ++move) {
    const auto sq = p.squeeze();
    int w = voids.front();
    for (int i : voids)
      if (sq[i] > sq[w]) w = i;
    p.active[w] = 0;
    p.build_pairs();
    p.relax(opt.max_iterations / 2, ftol);
    p.fill_grid(grid, w);
    double c = 0;
    p.x[w] = p.largest_void(grid, w, c);
    p.active[w] = 1;
    p.build_pairs();
    p.relax(opt.max_iterations, ftol);
    ++res.relocations;
    const double fit = p.fit_scale();
    if (fit > best_fit) best_fit = fit, best_x = p.x;
  }
  if (p.fit_scale() < best_fit) p.x = best_x;

  // 4. Last relaxation with the radii 2e-6 larger, so that the true radii end with strictly
  //    positive gaps; success is checked over all pairs and walls.
  p.s = 1 + 2e-6;
  p.build_pairs();
  p.relax(opt.final_iterations, ftol_final);
  p.s = 1;
  res.max_overlap = std::max(0.0, p.max_overlap(true));
  res.overlap_free = res.max_overlap <= 0;
  res.fit_scale = p.fit_scale();
  res.iterations = p.iterations;
  res.centres = std::move(p.x);
  return res;
}

}  // namespace pbx
