#include "setup/layer_setup.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <numeric>

#include <fmt/format.h>

#include "core/error.hpp"

namespace pbx {

namespace {

// Particles bucketed by grid cell (counting sort): neighbour searches within a few cells.
template <int D>
struct CellBuckets {
  std::vector<long> start;           // per cell, into order
  std::vector<std::uint32_t> order;  // particle indices, cell by cell
  std::array<long, D> n{};
  double inv_h = 0;
  Vec<D> origin;

  CellBuckets(const Grid<D>& g, const std::vector<Vec<D>>& x) : inv_h(1.0 / g.h), origin(g.origin) {
    long cells = 1;
    for (int d = 0; d < D; ++d) n[d] = g.n[d], cells *= n[d];
    start.assign(static_cast<std::size_t>(cells) + 1, 0);
    std::vector<long> cell(x.size());
    for (std::size_t p = 0; p < x.size(); ++p) {
      cell[p] = index(coords(x[p]));
      ++start[static_cast<std::size_t>(cell[p]) + 1];
    }
    std::partial_sum(start.begin(), start.end(), start.begin());
    order.resize(x.size());
    std::vector<long> fill(start.begin(), start.end() - 1);
    for (std::size_t p = 0; p < x.size(); ++p)
      order[static_cast<std::size_t>(fill[static_cast<std::size_t>(cell[p])]++)] = static_cast<std::uint32_t>(p);
  }
  std::array<long, D> coords(const Vec<D>& x) const {
    std::array<long, D> c;
    for (int d = 0; d < D; ++d)
      c[d] = std::clamp(static_cast<long>(std::floor((x[d] - origin[d]) * inv_h)), 0L, n[d] - 1);
    return c;
  }
  long index(const std::array<long, D>& c) const {
    long k = 0;
    for (int d = D - 1; d >= 0; --d) k = k * n[d] + c[d];
    return k;
  }
  // Calls f(q) for every particle q in the cells within `reach` cells of x's cell; stops when f
  // returns true, and returns whether one did.
  template <class F>
  bool any_near(const Vec<D>& x, long reach, F&& f) const {
    const auto c = coords(x);
    std::array<long, D> lo, hi, k;
    for (int d = 0; d < D; ++d)
      lo[d] = std::max(0L, c[d] - reach), hi[d] = std::min(n[d] - 1, c[d] + reach), k[d] = lo[d];
    while (true) {
      const long cell = index(k);
      for (long j = start[static_cast<std::size_t>(cell)]; j < start[static_cast<std::size_t>(cell) + 1]; ++j)
        if (f(order[static_cast<std::size_t>(j)])) return true;
      int d = 0;
      while (d < D && ++k[d] > hi[d]) k[d] = lo[d], ++d;
      if (d == D) return false;
    }
  }
};

}  // namespace

template <int D>
void setup_binder_layers(Scene<D>& sc, const DeckTable& root) {
  ContactMatrix& cm = sc.contact;
  if (!cm.has_layers()) return;

  // stiffnesses from the binder materials; the k-th binder_layer pair entry made layers[k]
  {
    const DeckTable contact = root.table("contact");
    std::size_t k = 0;
    for (const DeckTable& p : contact.tables("pair")) {
      if (p.string("law") != "binder_layer") continue;
      LayerLaw& law = cm.layers[k++];
      if (law.binder.empty()) continue;
      const auto it = std::find(sc.material_names.begin(), sc.material_names.end(), law.binder);
      if (it == sc.material_names.end())
        p.fail("binder", fmt::format("no material named '{}' in [materials]", law.binder));
      MaterialContext ctx;
      ctx.temperature = sc.control.temperature;
      ctx.name = law.binder;
      const auto binder = make_material<3>(root.table("materials").table(law.binder), ctx);
      layer_moduli(law, *binder, sc.control.end_time, p);
    }
  }

  // reference positions and bond flags
  auto& P = sc.particles;
  LayerParticles<D>& LP = sc.layer_data.particles;
  const std::size_t np = P.size();
  LP.X0 = P.x;
  LP.bonded.assign(np, 0);
  const double h = sc.grid.h, spacing = h / sc.settings.ppc;
  const bool coats = std::any_of(cm.layers.begin(), cm.layers.end(), [](const LayerLaw& l) { return l.from_coats; });
  if (coats && sc.grain_coat.size() != np)
    root.table("contact").fail("pair",
                               "binder_layer thickness = \"coats\" needs a packed specimen ([specimen] with [packing] "
                               "or specimen.packing_dir): the coats come from its grains");
  // the thickness of a contact's layer: one value, or the two grains' coats
  const auto thickness = [&](const LayerLaw& L, std::size_t p, std::size_t q) {
    return L.from_coats ? L.coat_scale * (sc.grain_coat[p] + sc.grain_coat[q]) : L.thickness;
  };
  double max_coat = 0;
  for (double c : sc.grain_coat) max_coat = std::max(max_coat, c);
  // A law's reach beyond touching: its bond gap; with film = "integrated" the band of one cell
  // whose nodes the two sides share, and the search covers the film out to film_extent x t
  const auto reach_of = [&](const LayerLaw& l, double t) {
    return l.integrated ? h : l.bond_within_thickness ? t : l.bond_gap;
  };
  const auto search_of = [&](const LayerLaw& l, double t) {
    return l.integrated ? std::max(reach_of(l, t), l.film_extent * t) : reach_of(l, t);
  };
  double gap = 0;  // the search reach: the largest of any law
  for (const auto& l : cm.layers)
    gap = std::max(gap, search_of(l, l.from_coats ? 2.0 * l.coat_scale * max_coat : l.thickness));
  // the bonded zone's depth: a law's bond_depth, else two cells or its deepest closure (closure x
  // its thickest layer) plus a cell, whichever is larger; the deepest of the laws
  double bond_r = 0;
  for (const auto& l : cm.layers) {
    const double t_max = l.from_coats ? 2.0 * l.coat_scale * max_coat : l.thickness;
    bond_r = std::max(bond_r, l.bond_depth > 0.0 ? l.bond_depth : std::max(2.0 * h, l.closure * t_max + h));
  }
  const double touch_r = 1.01 * spacing + gap;
  const auto layer_pair = [&](int a, int b) {
    return a != b && a < cm.fields && b < cm.fields && cm(a, b).law == ContactLaw::binder_layer;
  };
  const CellBuckets<D> cells(sc.grid, P.x);
  // q - p; across the extrusion only (a 2-D packing extruded through a 3-D die): every particle
  // layer then sees the 2-D geometry, without neighbours in other layers tilting its normal
  const auto apart = [&, axis = cm.extruded_axis](std::size_t q, std::size_t p) {
    Vec<D> d = P.x[q] - P.x[p];
    if (axis >= 0) d[axis] = 0.0;
    return d;
  };
  // touching particles, their contact normal (the mean direction to the touching particles of
  // the other side) and their layer's thickness (the two grains' coats with thickness = "coats")
  const auto pair_law = [&](int a, int b) -> const LayerLaw& {
    return cm.layers[static_cast<std::size_t>(cm(a, b).layer)];
  };
  std::vector<std::uint8_t> touching(np, 0);
  std::vector<Vec<D>> toward(np, Vec<D>::Zero());
  std::vector<double> inv_t(np, 0.0);
  // film = "integrated": per particle its nearest particle of another body, the local gap and
  // thickness there, and whether it faces that body (no particle of its own in front of it)
  const bool integrated =
      std::any_of(cm.layers.begin(), cm.layers.end(), [](const LayerLaw& l) { return l.integrated; });
  if (integrated && sc.grain_index.size() != np)
    root.table("contact").fail(
        "pair", "film = \"integrated\" needs the bodies of the particles (packed grains or [[geometry]] entries)");
  // refused up front, not at the first pair found: a 3-D scene whose films happen to meet no pair
  // would otherwise run with the bonded nodes left alone and no film at all
  if constexpr (D == 3)
    if (std::any_of(cm.layers.begin(), cm.layers.end(), [](const LayerLaw& l) { return l.bonds || l.join_gap_binder; }))
      root.table("contact").fail("pair",
                                 "film = \"bonds\" and gap_binder = \"join\" are built for 2-D scenes only (the "
                                 "pairs, their stable step and the binder's join are verified in 2-D only); use film "
                                 "= \"integrated\" with its free gap binder in 3-D");
  std::vector<int> other(np, -1);
  std::vector<long> nearest_of(np, -1);  // film = "bonds": the particle a facing particle ties to
  std::vector<double> local_gap(np, 0.0), local_t(np, 0.0), extent(np, 0.0);
  std::vector<std::uint8_t> faces(np, 0);
  const long touch_cells = static_cast<long>(std::ceil(touch_r / h)),
             bond_cells = static_cast<long>(std::ceil(bond_r / h));
#pragma omp parallel for schedule(static)
  for (std::size_t p = 0; p < np; ++p) {
    Vec<D> sum = Vec<D>::Zero();
    double scale_sum = 0;
    int n = 0;
    double nearest = std::numeric_limits<double>::infinity();
    long nearest_q = -1;
    cells.any_near(P.x[p], touch_cells, [&](std::uint32_t q) {
      const Vec<D> d = apart(q, p);
      if (!layer_pair(P.field[p], P.field[q])) return false;
      const LayerLaw& L = pair_law(P.field[p], P.field[q]);
      const double t = thickness(L, p, q), dist = d.norm();
      if (L.integrated && dist < nearest && dist <= 1.01 * spacing + search_of(L, t)) nearest = dist, nearest_q = q;
      if (dist > 1.01 * spacing + reach_of(L, t)) return false;
      sum += d / dist;
      // 1/t of this contact (the mean over the touching particles is the harmonic mean of t);
      // stiffnesses given per area directly carry 1
      scale_sum += L.binder.empty() ? 1.0 : 1.0 / t;
      ++n;
      return false;
    });
    const double len = sum.norm();
    touching[p] = len > 0.0;
    if (len > 0.0) toward[p] = sum / len, inv_t[p] = scale_sum / n;
    if (nearest_q >= 0) {
      const auto q = static_cast<std::size_t>(nearest_q);
      other[p] = sc.grain_index[q];
      nearest_of[p] = nearest_q;
      local_gap[p] = std::max(0.0, nearest - spacing);
      const LayerLaw& L = pair_law(P.field[p], P.field[q]);
      local_t[p] = thickness(L, p, q);
      extent[p] = L.film_extent;
      const Vec<D> e = apart(q, p) / nearest;
      faces[p] = !cells.any_near(P.x[p], 2, [&](std::uint32_t r) {
        if (sc.grain_index[r] != sc.grain_index[p] || r == p) return false;
        const Vec<D> d = apart(r, p);
        const double along = d.dot(e);  // in front of p, in its column towards the other body
        return along > 0.5 * spacing && (d - along * e).norm() < 0.71 * spacing;
      });
    }
  }
  if (integrated) {
    // per contact (this body, the other): S = sum a/(t + g) over the facing particles within
    // film_extent x t, W = sum a over those within the shared band; each touching particle then
    // carries S/W, so that the band's springs add up to the whole film (the particles' surface
    // patches a = spacing^(D-1) cancel, and with them the staircase of a curved surface)
    std::map<std::pair<int, int>, std::pair<double, double>> film;
    for (std::size_t p = 0; p < np; ++p) {
      if (other[p] < 0 || !faces[p]) continue;
      auto& [S, W] = film[{sc.grain_index[p], other[p]}];
      // the film reaches film_extent x t, and at least over the band (else the grid would meet
      // the two bodies there with a rigid Coulomb contact a cell before their surfaces do)
      if (local_gap[p] <= std::max(extent[p] * local_t[p], h)) S += 1.0 / (local_t[p] + local_gap[p]);
      if (local_gap[p] <= h) W += 1.0;
    }
    // film = "bonds": each facing particle within the film ties to its nearest particle of the other
    // body with half the film under its patch (the other side ties too)
    sc.layer_data.bonds.clear();
    for (std::size_t p = 0; p < np; ++p) {
      if (other[p] < 0 || !faces[p]) continue;
      const auto q = static_cast<std::size_t>(nearest_of[p]);
      const int layer = cm(P.field[p], P.field[q]).layer;
      const LayerLaw& L = cm.layers[static_cast<std::size_t>(layer)];
      // (a film whose gap binder joins a grain finds its pairs too, for the join below, and drops them after)
      if (!(L.bonds || L.join_gap_binder) || local_gap[p] > std::max(extent[p] * local_t[p], h)) continue;
      LayerBond<D> b;
      b.p = static_cast<std::uint32_t>(p);
      b.q = static_cast<std::uint32_t>(q);
      b.layer = layer;
      b.coef = 0.5 * std::pow(spacing, D - 1) / (local_t[p] + local_gap[p]);
      b.d0 = P.x[q] - P.x[p];
      b.n0 = b.d0.normalized();
      sc.layer_data.bonds.push_back(b);
    }
    // film = "bonds": the particles of a third body lying in a bonded pair's gap (the binder coats
    // between the two grains) are the binder the pair's springs already carry. Left as they are
    // they meet both grains by Coulomb contact, and with the bonded nodes letting the two grain
    // fields overlap they are crushed between them: on two slabs pressing a disk with binder strips
    // beside its contacts (KE + stress work)/punch work reached 1.46, on the quick specimen 2.1 by
    // 1 % strain (docs/theory/paper_study.md, "Films on particle pairs"). So each such particle
    // joins the field of the pair's nearer grain particle: it moves with that grain, keeps its own
    // material and stress, and the film is counted once. "In the gap": its centre within one
    // particle spacing of the segment joining the pair (half a spacing left some: 1.054; one to
    // one and a half spacings gave 0.999-1.000).
    if (!sc.layer_data.bonds.empty()) {
      std::vector<int> joins(np, -1);
      std::vector<double> closest(np, std::numeric_limits<double>::infinity());
      for (const auto& b : sc.layer_data.bonds) {
        if (!cm.layers[static_cast<std::size_t>(b.layer)].join_gap_binder) continue;  // gap_binder = "free"
        const Vec<D> a = P.x[b.p], ab = P.x[b.q] - P.x[b.p];
        const long reach = static_cast<long>(std::ceil((0.5 * ab.norm() + spacing) / h)) + 1;
        cells.any_near(a + 0.5 * ab, reach, [&](std::uint32_t r) {
          const int fr = P.field[r];
          if (fr == P.field[b.p] || fr == P.field[b.q] || layer_pair(fr, P.field[b.p])) return false;
          const double s = std::clamp((P.x[r] - a).dot(ab) / ab.squaredNorm(), 0.0, 1.0);
          const double dist = (P.x[r] - (a + s * ab)).norm();
          if (dist > spacing || dist >= closest[r]) return false;
          closest[r] = dist;
          joins[r] = s < 0.5 ? P.field[b.p] : P.field[b.q];
          return false;
        });
      }
      for (std::size_t r = 0; r < np; ++r)
        if (joins[r] >= 0) P.field[r] = joins[r], ++sc.layer_data.gap_particles_joined;
      // only film = "bonds" keeps its pairs as springs; an integrated film's film stays at the nodes
      std::erase_if(sc.layer_data.bonds,
                    [&](const LayerBond<D>& b) { return !cm.layers[static_cast<std::size_t>(b.layer)].bonds; });
    }
    for (std::size_t p = 0; p < np; ++p) {
      if (!touching[p] || other[p] < 0) continue;
      // a contact with no facing particle in the band carries no film here: Coulomb
      const auto it = film.find({sc.grain_index[p], other[p]});
      const double S = it != film.end() ? it->second.first : 0.0, W = it != film.end() ? it->second.second : 0.0;
      if (S > 0.0 && W > 0.0)
        inv_t[p] = S / W;
      else
        touching[p] = 0, inv_t[p] = 0.0;
    }
  }
  for (std::size_t p = 0; p < np; ++p)
    if (touching[p] && !(std::isfinite(inv_t[p]) && inv_t[p] > 0.0))
      root.table("contact").fail("pair",
                                 fmt::format("binder_layer: particle {} at ({:.4g}, {:.4g}) m touches a grain with no "
                                             "binder coat (zero layer thickness)",
                                             p, P.x[p][0], P.x[p][1]));
  // bonded particles: within two cells of a touching particle of their own field; their normal
  // and 1/t are the means of those particles'
  LP.N0.assign(np, Vec<D>::Zero());
  LP.inv_t.assign(np, 0.0);
#pragma omp parallel for schedule(static)
  for (std::size_t p = 0; p < np; ++p) {
    Vec<D> sum = Vec<D>::Zero();
    double scale_sum = 0;
    int n = 0;
    cells.any_near(P.x[p], bond_cells, [&](std::uint32_t q) {
      if (touching[q] && P.field[q] == P.field[p] && apart(q, p).norm() <= bond_r)
        sum += toward[q], scale_sum += inv_t[q], ++n;
      return false;
    });
    const double len = sum.norm();
    LP.bonded[p] = len > 0.0;
    if (len > 0.0) LP.N0[p] = sum / len, LP.inv_t[p] = scale_sum / n;
  }
}

template void setup_binder_layers<2>(Scene<2>&, const DeckTable&);
template void setup_binder_layers<3>(Scene<3>&, const DeckTable&);

}  // namespace pbx
