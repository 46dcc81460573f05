#include "microstructure/packing.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

#include <fmt/format.h>

#include "core/error.hpp"
#include "io/deck.hpp"
#include "microstructure/colouring.hpp"
#include "microstructure/disk_packer.hpp"
#include "microstructure/union_area.hpp"

namespace pbx {

double PackingSpec::tmd() const {
  const double wt = tatb_mass / (tatb_mass + binder_mass), wb = 1.0 - wt;
  return 1.0 / (wt / tatb_density + wb / binder_density);
}

double PackingSpec::binder_per_tatb_area() const { return (binder_mass / tatb_mass) * (tatb_density / binder_density); }

namespace {

DiameterMode read_mode(const DeckTable& t, double dmin, double dmax) {
  DiameterMode m;
  m.mean = t.positive("mean", dim::length);
  m.spread = t.non_negative("spread", dim::length, 0.0);
  m.share = t.in_range("share", 0.0, 1.0);
  if (m.spread == 0 && (m.mean < dmin || m.mean > dmax))
    t.fail("mean", "lies outside [diameter_min, diameter_max] and spread is 0");
  if (m.spread > 0) {
    const auto Phi = [](double z) { return 0.5 * std::erfc(-z / std::numbers::sqrt2); };
    const double p = Phi((dmax - m.mean) / m.spread) - Phi((dmin - m.mean) / m.spread);
    if (p < 1e-3)
      t.fail("mean", fmt::format("only {:.2g} of this normal lies in [diameter_min, diameter_max]: move the mean "
                                 "into the range or widen the spread",
                                 p));
  }
  return m;
}

}  // namespace

PackingSpec read_packing_spec(const DeckTable& t) {
  PackingSpec s;
  const auto box = t.quantities("box", dim::length);
  if (box.size() != 2 || !(box[0] > 0) || !(box[1] > 0)) t.fail("box", "expected two positive lengths [width, height]");
  s.box = {box[0], box[1]};
  const long seed = t.integer("seed", 1);
  if (seed < 0) t.fail("seed", "must be >= 0");
  s.seed = static_cast<std::uint64_t>(seed);

  if (t.has("mass_ratio")) {
    const auto r = t.quantities("mass_ratio", dim::none);
    if (r.size() != 2) t.fail("mass_ratio", "expected [TATB, binder] parts, e.g. [95, 5]");
    if (!(r[0] > 0) || !(r[1] > 0)) t.fail("mass_ratio", "both parts must be > 0");
    s.tatb_mass = r[0];
    s.binder_mass = r[1];
  }
  s.tatb_density = t.positive("tatb_density", dim::density, 1934.0);
  s.binder_density = t.positive("binder_density", dim::density, 2020.0);

  if (t.has("porosity") == t.has("density")) t.fail("porosity", "give exactly one of porosity and density");
  if (t.has("porosity")) {
    s.porosity = t.number("porosity");
    if (!(s.porosity >= 0 && s.porosity < 1))
      t.fail("porosity", fmt::format("must lie in [0, 1) (got {})", s.porosity));
  } else {
    const double rho = t.positive("density", dim::density);
    s.porosity = 1.0 - rho / s.tmd();
    if (!(s.porosity >= 0))
      t.fail("density", fmt::format("exceeds the theoretical maximum density {:.4f} g/cm3", s.tmd() / 1000));
  }
  s.tolerance = t.in_range("porosity_tolerance", 1e-6, 0.1, 0.002);

  s.sizes.dmin = t.positive("diameter_min", dim::length);
  s.sizes.dmax = t.positive("diameter_max", dim::length);
  if (s.sizes.dmin > s.sizes.dmax)
    t.fail("diameter_min", fmt::format("is larger than diameter_max ({:.4g} > {:.4g} m)", s.sizes.dmin, s.sizes.dmax));
  if (2 * s.sizes.dmax > std::min(s.box.x(), s.box.y()))
    t.fail("diameter_max", "must be at most half the smaller box side");
  {
    // Every fine grain is placed one at a time and the whole packing relaxed after each, so the
    // cost grows faster than N^2: refuse a box that could need more grains than the packer is for
    // (the paper's box holds about 100) instead of running for days or out of memory.
    constexpr double kMaxGrains = 20000;
    const double at_most = s.box.prod() / (0.25 * M_PI * s.sizes.dmin * s.sizes.dmin);
    if (at_most > kMaxGrains)
      t.fail("diameter_min", fmt::format("the {:.3g} x {:.3g} m box could need up to {:.3g} grains of {:.3g} m; this "
                                         "packer is built for at most {:.0f} (enlarge diameter_min or shrink box)",
                                         s.box.x(), s.box.y(), at_most, s.sizes.dmin, kMaxGrains));
  }
  s.sizes.modes[0] = read_mode(t.table("coarse"), s.sizes.dmin, s.sizes.dmax);
  s.sizes.modes[1] = t.has("fine") ? read_mode(t.table("fine"), s.sizes.dmin, s.sizes.dmax) : DiameterMode{};
  if (std::abs(s.sizes.modes[0].share + s.sizes.modes[1].share - 1.0) > 1e-9)
    t.fail("coarse", "coarse.share + fine.share must be 1");
  const std::string by = t.string("share_by", "area");
  if (by != "area" && by != "count") t.fail("share_by", "expected \"area\" or \"count\"");
  s.sizes.by_area = by == "area";

  const std::string coat = t.string("coat", "proportional");
  if (coat != "proportional" && coat != "uniform") t.fail("coat", "expected \"proportional\" or \"uniform\"");
  s.uniform_coat = coat == "uniform";
  s.contact_gap = t.non_negative("contact_gap", dim::length, 2e-6);
  const std::string boundary = t.string("boundary", "periodic");
  if (boundary != "periodic" && boundary != "walls") t.fail("boundary", "expected \"periodic\" or \"walls\"");
  s.periodic = boundary == "periodic";
  const long attempts = t.integer("attempts", 8);
  if (attempts < 1 || attempts > 1000) t.fail("attempts", "must lie in [1, 1000]");
  s.attempts = static_cast<int>(attempts);
  if (t.has("tiles")) {
    const auto n = t.quantities("tiles", dim::none);
    if (n.size() != 2) t.fail("tiles", "expected [copies along x, copies along y], e.g. [2, 1]");
    for (int k = 0; k < 2; ++k)
      if (!(n[k] >= 1 && n[k] <= 64 && n[k] == std::floor(n[k])))
        t.fail("tiles", fmt::format("entry {} must be a whole number in [1, 64] (got {})", k, n[k]));
    if (!s.periodic && (n[0] > 1 || n[1] > 1))
      t.fail("tiles",
             "needs boundary = \"periodic\": copies of a packing with walls would meet along flat, grain-free seams");
    s.tiles = {static_cast<int>(n[0]), static_cast<int>(n[1])};
  }
  return s;
}

std::vector<Disk> disks_in_box(const Packing& p, bool coated) {
  std::vector<Disk> out;
  for (int g = 0; g < static_cast<int>(p.grains.size()); ++g) {
    const Grain& gr = p.grains[g];
    const double r = 0.5 * gr.diameter + (coated ? gr.coat : 0.0);
    const int reach = p.periodic ? 1 : 0;
    for (int i = -reach; i <= reach; ++i)
      for (int j = -reach; j <= reach; ++j) {
        const Eigen::Vector2d c = gr.centre + Eigen::Vector2d(i * p.box.x(), j * p.box.y());
        if (c.x() + r <= 0 || c.x() - r >= p.box.x() || c.y() + r <= 0 || c.y() - r >= p.box.y()) continue;
        out.push_back({c, r, g});
      }
  }
  return out;
}

namespace {

// Largest relative diameter reduction accepted to remove the last overlaps of a jammed packing.
constexpr double kMaxShrink = 0.01;

double union_area(const Packing& p, bool coated) {
  std::vector<Circle> c;
  for (const Disk& d : disks_in_box(p, coated)) c.push_back({d.centre, d.radius});
  return union_area_in_box(c, p.box);
}

// Coat thickness per unit of the rule (diameter for proportional coats, 1 m for uniform ones).
void set_coats(Packing& p, bool uniform, double s) {
  for (auto& g : p.grains) g.coat = uniform ? s : s * g.diameter;
}

}  // namespace

void measure(Packing& p) {
  PackingStats& st = p.stats;
  const double box_area = p.box.prod();
  if (p.image.nx > 0) {
    long tatb = 0, binder = 0;
    for (int l : p.image.label) tatb += l >= 0, binder += l == -1;
    const double px = p.image.pixel * p.image.pixel;
    st.tatb_area_fraction = tatb * px / box_area;
    st.binder_area_fraction = binder * px / box_area;
  } else {
    const double tatb = union_area(p, false);
    st.tatb_area_fraction = tatb / box_area;
    st.binder_area_fraction = (union_area(p, true) - tatb) / box_area;
  }
  st.porosity = 1.0 - st.tatb_area_fraction - st.binder_area_fraction;
  const double mt = st.tatb_area_fraction * p.tatb_density, mb = st.binder_area_fraction * p.binder_density;
  st.density = mt + mb;
  st.tatb_mass_fraction = mt / (mt + mb);
  st.tmd = 1.0 / (st.tatb_mass_fraction / p.tatb_density + (1.0 - st.tatb_mass_fraction) / p.binder_density);
  st.coat_min = st.coat_max = p.grains.empty() ? 0.0 : p.grains[0].coat;
  st.grains_coarse = st.grains_fine = 0;
  st.colours = 0;
  for (const auto& g : p.grains) {
    st.coat_min = std::min(st.coat_min, g.coat);
    st.coat_max = std::max(st.coat_max, g.coat);
    st.grains_coarse += g.mode == 0;
    st.grains_fine += g.mode == 1;
    st.colours = std::max(st.colours, g.colour + 1);
  }
}

Packing generate_packing(const PackingSpec& spec) {
  const double box_area = spec.box.prod();
  const double beta = spec.binder_per_tatb_area();
  // Porosity fixes the TATB area: solids = TATB (1 + beta), whatever shape the binder takes.
  const double tatb_area = (1.0 - spec.porosity) * box_area / (1.0 + beta);
  Rng size_rng(spec.seed);
  const auto sample = sample_diameters(spec.sizes, tatb_area, 0.5 * spec.tolerance * box_area / (1.0 + beta), size_rng);

  std::vector<double> radius, wall_radius;
  std::vector<bool> into_voids;
  for (const auto& s : sample) {
    radius.push_back(0.5 * s.diameter);
    wall_radius.push_back(0.5 * s.diameter);
    // Coarse grains are placed at random and grown; fine ones then fill the largest voids.
    into_voids.push_back(s.mode == 1);
  }
  DiskPackerOptions opt;
  opt.periodic = spec.periodic;

  DiskPackerResult best;
  std::vector<double> diameter(sample.size());
  for (std::size_t i = 0; i < sample.size(); ++i) diameter[i] = sample[i].diameter;
  int shrunk = 0, used = 0;
  double max_shrink = 0;
  for (int attempt = 0; attempt < spec.attempts; ++attempt) {
    // Placements differ per attempt; the diameters are the same sample every time.
    Rng rng(spec.seed * 0x9E3779B97F4A7C15ull + 0xD1B54A32D192ED03ull * (attempt + 1));
    auto res = pack_disks(radius, wall_radius, into_voids, spec.box, rng, opt);
    if (!res.overlap_free) {
      // A jammed packing whose last overlaps are tiny is accepted after shrinking the smaller
      // grain of each overlapping pair just enough, if no grain loses more than kMaxShrink of its
      // diameter or drops below diameter_min, and the porosity stays within tolerance.
      std::vector<double> d = diameter;
      const std::size_t n = d.size();
      for (std::size_t i = 0; i < n; ++i)
        for (std::size_t j = i + 1; j < n; ++j) {
          Eigen::Vector2d sep = res.centres[j] - res.centres[i];
          if (spec.periodic)
            for (int k = 0; k < 2; ++k) sep[k] -= spec.box[k] * std::round(sep[k] / spec.box[k]);
          const double overlap = 0.5 * (d[i] + d[j]) - sep.norm();
          if (overlap < 0) continue;
          const std::size_t small = d[i] < d[j] ? i : j;
          d[small] -= 2 * overlap + 1e-12 * d[small];
        }
      if (!spec.periodic)
        for (std::size_t i = 0; i < n; ++i)
          for (int k = 0; k < 2; ++k)
            d[i] = std::min({d[i], 2 * res.centres[i][k], 2 * (spec.box[k] - res.centres[i][k])});
      double area = 0, worst = 0;
      bool ok = true;
      int count = 0;
      for (std::size_t i = 0; i < n; ++i) {
        area += 0.25 * std::numbers::pi * d[i] * d[i];
        worst = std::max(worst, 1 - d[i] / diameter[i]);
        count += d[i] < diameter[i];
        ok = ok && d[i] >= spec.sizes.dmin;
      }
      const double porosity = 1.0 - (1.0 + beta) * area / box_area;
      if (ok && worst <= kMaxShrink && std::abs(porosity - spec.porosity) <= spec.tolerance) {
        diameter = d;
        shrunk = count;
        max_shrink = worst;
        res.overlap_free = true;
        res.max_overlap = 0;
      }
    }
    used = attempt + 1;
    if (attempt == 0 || res.fit_scale > best.fit_scale || res.overlap_free) best = std::move(res);
    if (best.overlap_free) break;
  }

  Packing p;
  p.box = spec.box;
  p.periodic = spec.periodic;
  p.seed = spec.seed;
  p.tatb_density = spec.tatb_density;
  p.binder_density = spec.binder_density;
  p.contact_gap = spec.contact_gap;
  p.grains_shrunk = shrunk;
  p.max_shrink = max_shrink;
  p.attempt = used;
  for (std::size_t i = 0; i < sample.size(); ++i)
    p.grains.push_back({best.centres[i], diameter[i], 0, 0, sample[i].mode});

  if (!best.overlap_free) {
    // Best reached: the same arrangement with every diameter shrunk by the one factor that removes
    // the last overlap (pairs and walls), i.e. the TATB area this jammed packing can hold.
    double shrink = 1.0;
    for (std::size_t i = 0; i < p.grains.size(); ++i) {
      const Grain& a = p.grains[i];
      if (!p.periodic)
        for (int k = 0; k < 2; ++k)
          shrink = std::min({shrink, a.centre[k] / (0.5 * a.diameter), (p.box[k] - a.centre[k]) / (0.5 * a.diameter)});
      for (std::size_t j = i + 1; j < p.grains.size(); ++j) {
        const Grain& b = p.grains[j];
        Eigen::Vector2d d = b.centre - a.centre;
        if (p.periodic)
          for (int k = 0; k < 2; ++k) d[k] -= p.box[k] * std::round(d[k] / p.box[k]);
        shrink = std::min(shrink, d.norm() / (0.5 * (a.diameter + b.diameter)));
      }
    }
    const double kept = shrink * shrink * tatb_area;
    const double reached = 1.0 - (1.0 + beta) * kept / box_area;
    throw InputError(
        fmt::format("packing.porosity: {:.4f} cannot be reached with these grain sizes: after {} attempts the densest "
                    "overlap-free packing found has porosity {:.4f} (TATB area fraction {:.4f}, grains shrunk by "
                    "{:.3f}). Raise porosity, add "
                    "attempts, widen [diameter_min, diameter_max] or change the mode shares (a larger size ratio "
                    "between the modes packs denser).",
                    spec.porosity, spec.attempts, reached, kept / box_area, shrink));
  }

  // Coat thickness from the exact mass balance: union(coats) - TATB = beta * TATB. The union area
  // grows monotonically with the coat, so bisection converges to round-off.
  const double tatb = union_area(p, false);
  const double target = (1.0 + beta) * tatb;
  double lo = 0, hi = spec.uniform_coat ? 0.5 * spec.sizes.dmin : 0.5;
  for (int k = 0; k < 200 && hi - lo > 1e-15 * hi; ++k) {
    const double mid = 0.5 * (lo + hi);
    set_coats(p, spec.uniform_coat, mid);
    (union_area(p, true) < target ? lo : hi) = mid;
  }
  set_coats(p, spec.uniform_coat, 0.5 * (lo + hi));
  colour_grains(p);
  measure(p);
  if (std::abs(p.stats.porosity - spec.porosity) > spec.tolerance)
    throw InputError(fmt::format("packing.porosity: reached {:.5f} instead of {:.5f} (tolerance {})", p.stats.porosity,
                                 spec.porosity, spec.tolerance));
  return spec.tiles == std::array<int, 2>{1, 1} ? p : tile_packing(p, spec.tiles);
}

Packing tile_packing(const Packing& cell, std::array<int, 2> tiles) {
  if (!(tiles[0] >= 1 && tiles[1] >= 1)) throw InputError("packing.tiles: entries must be >= 1");
  if (!cell.periodic)
    throw InputError("packing.tiles: needs a periodic packing (boundary = \"periodic\"); this one has walls");
  if (cell.image.nx > 0) throw InputError("packing.tiles: an imported image is not a periodic cell and is not tiled");
  Packing p = cell;
  p.box = {cell.box.x() * tiles[0], cell.box.y() * tiles[1]};
  p.tiles = {cell.tiles[0] * tiles[0], cell.tiles[1] * tiles[1]};
  p.grains_shrunk = cell.grains_shrunk * tiles[0] * tiles[1];
  p.grains.clear();
  p.grains.reserve(cell.grains.size() * static_cast<std::size_t>(tiles[0] * tiles[1]));
  for (int j = 0; j < tiles[1]; ++j)
    for (int i = 0; i < tiles[0]; ++i)
      for (Grain g : cell.grains) {
        g.centre += Eigen::Vector2d(i * cell.box.x(), j * cell.box.y());
        p.grains.push_back(g);
      }
  measure(p);
  return p;
}

}  // namespace pbx
