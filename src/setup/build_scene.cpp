// Deck -> scene: every section of a run deck read, validated and turned into the engine's input
// (solver/scene.hpp). The only place besides the other setup/ files that walks a deck.
#include "setup/build_scene.hpp"
#include "setup/contact_deck.hpp"
#include "setup/layer_setup.hpp"

#include <algorithm>
#include <cmath>
#include <functional>
#include <map>
#include <numeric>

#include <unistd.h>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "analysis/run_analysis.hpp"
#include "core/error.hpp"
#include "io/deck.hpp"
#include "microstructure/colouring.hpp"
#include "microstructure/packing.hpp"
#include "microstructure/rasterise.hpp"
#include "grid/strip_bins.hpp"

namespace pbx {

namespace {

template <int D>
Vec<D> read_vec(const DeckTable& t, const std::string& key, const Dimension& d,
                std::optional<Vec<D>> def = std::nullopt) {
  if (!t.has(key)) {
    if (def) return *def;
    t.fail(key, fmt::format("required key missing (an array of {} quantities)", D));
  }
  auto v = t.quantities(key, d);
  if (static_cast<int>(v.size()) != D) t.fail(key, fmt::format("expected {} components, got {}", D, v.size()));
  Vec<D> out;
  for (int i = 0; i < D; ++i) out[i] = v[static_cast<std::size_t>(i)];
  return out;
}

// An integer key that sizes something: range-checked before the cast, so a huge value is an
// error naming the key instead of wrapping around to a small one.
int int_in(const DeckTable& t, const std::string& key, long lo, long hi, long def) {
  const long v = t.integer(key, def);
  if (v < lo || v > hi) t.fail(key, fmt::format("must lie in [{}, {}] (got {})", lo, hi, v));
  return static_cast<int>(v);
}

// Memory per node and deformable velocity field (mass and seven 2-vectors, grid/grid.hpp; 3-D
// needs more, so this errs low there) and per particle (docs/performance.md: 268 bytes per
// particle, grid included, at 2 x 2 particles per cell).
constexpr double kGridBytesPerNodeField = 120, kParticleBytes = 300;
// binder_layer sums: reference offset, deformation gradient, bond mass (2-D: 2 + 4 + 1 doubles)
constexpr double kLayerBytesPerNodeField = 8.0 * 14;

double physical_memory_bytes() {
  const long pages = sysconf(_SC_PHYS_PAGES), size = sysconf(_SC_PAGE_SIZE);
  return pages > 0 && size > 0 ? static_cast<double>(pages) * static_cast<double>(size) : 1e300;
}

// Refuses, naming `key`, what would need more bytes than the machine has: "<what> need(s) N GB,
// more than this machine's M GB".
void check_fits(const DeckTable& t, const std::string& key, double bytes, const std::string& what) {
  const double have = physical_memory_bytes();
  if (!(bytes < have))
    t.fail(key,
           fmt::format("{} need about {:.3g} GB, more than this machine's {:.3g} GB", what, bytes / 1e9, have / 1e9));
}

// A region of space a geometry entry or rigid body fills.
template <int D>
struct Shape {
  std::function<bool(const Vec<D>&)> contains;
  Vec<D> lo, hi;  // bounding box
};

template <int D>
Shape<D> read_shape(const DeckTable& t) {
  const std::string kind = t.string("shape", "rectangle");
  Shape<D> s;
  if (kind == "rectangle") {
    s.lo = read_vec<D>(t, "min", dim::length);
    s.hi = read_vec<D>(t, "max", dim::length);
    for (int d = 0; d < D; ++d)
      if (!(s.hi[d] > s.lo[d])) t.fail("max", "must exceed 'min' in every component");
    const Vec<D> lo = s.lo, hi = s.hi;
    s.contains = [lo, hi](const Vec<D>& x) {
      for (int d = 0; d < D; ++d)
        if (x[d] < lo[d] || x[d] > hi[d]) return false;
      return true;
    };
  } else if (kind == "disk") {
    const Vec<D> c = read_vec<D>(t, "center", dim::length);
    const double r = t.positive("radius", dim::length);
    s.lo = c.array() - r;
    s.hi = c.array() + r;
    s.contains = [c, r](const Vec<D>& x) { return (x - c).squaredNorm() <= r * r; };
  } else {
    t.fail("shape", fmt::format("unknown shape '{}' (known: rectangle, disk)", kind));
  }
  return s;
}

// Centres of the ppc^D sub-cells of every grid cell whose centre lies in `inside`, row-major over
// cells (so particle storage is sorted by cell). Calls emit(position).
template <int D>
void seed_subcells(const Grid<D>& g, int ppc, const Vec<D>& lo, const Vec<D>& hi,
                   const std::function<void(const Vec<D>&)>& emit) {
  std::array<long, D> c0, c1;
  for (int d = 0; d < D; ++d) {
    c0[d] = std::max(0L, static_cast<long>(std::floor((lo[d] - g.origin[d]) / g.h)));
    c1[d] = std::min(g.n[d] - 1, static_cast<long>(std::ceil((hi[d] - g.origin[d]) / g.h)));
  }
  for (int d = 0; d < D; ++d)
    if (c1[d] <= c0[d]) return;
  const double sub = g.h / ppc;
  std::array<long, D> c = c0;
  while (true) {
    // every sub-cell of cell c
    std::array<int, D> s{};
    while (true) {
      Vec<D> x;
      for (int d = 0; d < D; ++d) x[d] = g.origin[d] + c[d] * g.h + (s[d] + 0.5) * sub;
      emit(x);
      int d = 0;
      while (d < D && ++s[d] == ppc) {
        s[d] = 0;
        ++d;
      }
      if (d == D) break;
    }
    int d = 0;
    while (d < D && ++c[d] >= c1[d]) {
      c[d] = c0[d];
      ++d;
    }
    if (d == D) break;
  }
}

}  // namespace

int deck_dimension(const Deck& deck) {
  const DeckTable root = deck.root();
  if (!root.has("run")) return 2;  // build_scene names the missing table
  return int_in(root.table("run"), "dimension", 2, 3, 2);
}

template <int D>
Scene<D> build_scene(const Deck& deck, SceneNotes notes) {
  Scene<D> sc;
  const DeckTable root = deck.root();

  // How the run is to be analysed (a study writes its [analysis] table into each run deck, so that
  // a deck taken out of the study and run alone is analysed as the study analysed it: run.json keeps
  // the deck, and `pbxmpm analyze` reads the table from there). Not part of the simulation; checked
  // here so that a misspelt key fails before the run, not after it.
  if (auto a = root.optional_table("analysis")) (void)AnalysisOptions::from_deck(*a);

  // ---- run control
  const DeckTable run = root.table("run");
  if (const int dim = int_in(run, "dimension", 2, 3, 2); dim != D)
    run.fail("dimension", fmt::format("{}: this deck is built as a {}-D scene here", dim, D));
  sc.description = run.string("title", "");
  sc.control.temperature = run.positive("temperature", dim::temperature, 293.0);
  sc.control.history_points = int_in(run, "history_points", 2, 10'000'000, 400);
  sc.control.snapshots = int_in(run, "snapshots", 0, 100'000, 10);

  // ---- solver settings
  if (auto s = root.optional_table("solver")) {
    const std::string integ = s->string("integrator", "usl");
    if (integ == "musl")
      sc.settings.integrator = Integrator::musl;
    else if (integ == "usl")
      sc.settings.integrator = Integrator::usl;
    else if (integ == "usf")
      sc.settings.integrator = Integrator::usf;
    else
      s->fail("integrator", "unknown integrator '" + integ + "' (known: usf, usl, musl)");
    sc.settings.flip = s->in_range("flip", 0.0, 1.0, 0.99);
    sc.settings.cfl = s->number("cfl", 0.4);
    if (!(sc.settings.cfl > 0 && sc.settings.cfl < 1)) s->fail("cfl", "must lie in (0, 1)");
    sc.settings.mass_scaling = s->number("mass_scaling", 1.0);
    if (!(sc.settings.mass_scaling >= 1.0)) s->fail("mass_scaling", "must be >= 1");
    // beyond 1e4 the wave speed falls 100-fold and no die run stays quasi-static
    if (!(sc.settings.mass_scaling <= 1e4)) s->fail("mass_scaling", "must be <= 10000");
    sc.settings.gravity = read_vec<D>(*s, "gravity", dim::acceleration, Vec<D>::Zero());
  }

  // ---- grid
  const DeckTable gt = root.table("grid");
  const double h = gt.positive("cell_size", dim::length);
  try {
    sc.settings.kernel = kernel_from_name(gt.string("shape_function", "ugimp"));
  } catch (const InputError& e) {
    gt.fail("shape_function", e.what());
  }
  sc.settings.ppc = int_in(gt, "particles_per_cell", 1, 8, 2);
  sc.grid.h = h;

  std::optional<DeckTable> die_t = root.optional_table("die");
  Vec<D> gmin, gmax;
  int wall_cells = 2;
  if (die_t) {
    Die die;
    die.width = die_t->positive("width", dim::length);
    die.height = die_t->positive("height", dim::length);
    if constexpr (D == 3)
      die.depth = die_t->positive("depth", dim::length);
    else if (die_t->has("depth"))
      die_t->fail("depth", "applies to a 3-D die only (run.dimension = 3); a 2-D die is per metre of depth");
    die.punch_velocity = die_t->positive("punch_velocity", dim::velocity);
    die.ramp_strain = die_t->number("ramp_strain", kDefaultRampStrain);
    if (!(die.ramp_strain >= 0 && die.ramp_strain < 1)) die_t->fail("ramp_strain", "must lie in [0, 1)");
    wall_cells = int_in(*die_t, "wall_cells", 1, 1000, 2);
    for (auto [key, len] :
         {std::pair{"width", die.width}, std::pair{"height", die.height}, std::pair{"depth", die.depth}}) {
      if (len == 0.0) continue;  // depth of a 2-D die
      const double cells = len / h;
      if (std::abs(cells - std::round(cells)) > 1e-6 * cells)
        die_t->fail(key,
                    fmt::format("must be a whole number of cells (grid.cell_size = {} m gives {} cells)", h, cells));
    }
    sc.control.end_strain = run.number("end_strain");
    if (!(sc.control.end_strain > 0 && sc.control.end_strain < 0.5)) run.fail("end_strain", "must lie in (0, 0.5)");
    const double pad = (wall_cells + 2) * h;
    gmin = Vec<D>::Constant(-pad);
    gmax[0] = die.width + pad;
    gmax[1] = die.height + pad;
    if constexpr (D == 3) gmax[2] = die.depth + pad;
    sc.control.end_time = die.time_at_strain(sc.control.end_strain);
    if (die.ramp_strain >= sc.control.end_strain) run.fail("end_strain", "must exceed die.ramp_strain");
    sc.die = die;
  } else {
    gmin = read_vec<D>(gt, "min", dim::length);
    gmax = read_vec<D>(gt, "max", dim::length);
    sc.control.end_time = run.positive("end_time", dim::time);
  }
  sc.grid.origin = gmin;
  std::array<double, D> nodes_per_axis{};
  double nodes = 1;
  for (int d = 0; d < D; ++d) {
    if (!(gmax[d] > gmin[d])) gt.fail("max", "must exceed 'min' in every component");
    nodes_per_axis[static_cast<std::size_t>(d)] = std::ceil((gmax[d] - gmin[d]) / h - 1e-9) + 1;
    nodes *= nodes_per_axis[static_cast<std::size_t>(d)];
  }
  // Refuse a grid this machine cannot hold before allocating any of it (and before the casts
  // below): a mistyped size would otherwise end in std::bad_alloc or in swapping. The exact check,
  // with the number of velocity fields, follows when the fields are known.
  check_fits(gt, "cell_size", nodes * kGridBytesPerNodeField,
             fmt::format("{:.3g} nodes of {:.3g} m spacing ({}), one velocity field,", nodes, h,
                         die_t ? "die plus walls" : "[grid] min to max"));
  for (int d = 0; d < D; ++d) sc.grid.n[d] = static_cast<long>(nodes_per_axis[static_cast<std::size_t>(d)]);

  // ---- materials (ordered by name: the order is the material index)
  const DeckTable mats = root.table("materials");
  std::map<std::string, int> mat_index;
  MaterialContext ctx;
  ctx.temperature = sc.control.temperature;
  for (const auto& name : mats.keys()) {
    ctx.name = name;
    mat_index[name] = static_cast<int>(sc.materials.size());
    sc.material_names.push_back(name);
    sc.materials.push_back(make_material<D>(mats.table(name), ctx));
  }
  if (sc.materials.empty()) mats.fail("", "at least one material is required");

  // ---- a packed specimen ([specimen] + [packing]) fills the die; [[geometry]] entries add bodies
  std::map<std::string, int> field_index;
  const int ppc = sc.settings.ppc;
  bool extruded_specimen = false;  // a 2-D packing extruded through a 3-D die (grains_3d = "cylinders")
  sc.grid.stride[0] = 1;
  for (int d = 1; d < D; ++d) sc.grid.stride[d] = sc.grid.stride[d - 1] * sc.grid.n[d - 1];
  if (auto spec_t = root.optional_table("specimen")) {
    {
      if (!sc.die) spec_t->fail("grain_material", "a packed specimen needs a [die]");
      // In 3-D the packing is 2-D: its disks are extruded through the die's depth (cylinders), the
      // specimen a slab between the die's frictionless front and back walls, i.e. plane strain
      // computed in 3-D. Sphere packings are not offered: random packings of rigid spheres stop
      // near 64-80 % solids, short of the paper's 91-95 % without a compaction stage.
      int layers = 1;
      const double sub = h / ppc;
      if constexpr (D == 3) {
        const std::string how = spec_t->string("grains_3d", "");
        if (how != "cylinders")
          spec_t->fail("grains_3d", how.empty()
                                        ? std::string("a 3-D packed specimen needs grains_3d = \"cylinders\" (the 2-D "
                                                      "packing's disks extruded through die.depth; spheres are not "
                                                      "offered)")
                                        : fmt::format("must be \"cylinders\" (got \"{}\"): sphere packings are not "
                                                      "offered (rigid spheres stop near 64-80 % solids, short of the "
                                                      "paper's porosities)",
                                                      how));
        extruded_specimen = true;
        // the contact normals of an extruded specimen leave z out (ContactMatrix::extruded_axis),
        // which a body not uniform in z would not bear
        if (root.has("geometry"))
          root.fail("geometry",
                    "a packed specimen extruded through the depth (specimen.grains_3d) takes no "
                    "[[geometry]] bodies: its contact normals leave out z, which they are not uniform in");
        layers = static_cast<int>(std::lround(sc.die->depth / sub));
        if (layers < 1 || std::abs(layers * sub - sc.die->depth) > 1e-9 * sc.die->depth)
          root.table("die").fail("depth", fmt::format("a packed specimen fills the depth with whole particle layers: "
                                                      "give a multiple of cell_size / particles_per_cell ({} m)",
                                                      sub));
      } else if (spec_t->has("grains_3d")) {
        spec_t->fail("grains_3d", "applies to 3-D runs only (run.dimension = 3)");
      }
      auto material_of = [&](const char* key) {
        const std::string name = spec_t->string(key);
        auto it = mat_index.find(name);
        if (it == mat_index.end()) spec_t->fail(key, fmt::format("no material named '{}' in [materials]", name));
        return it->second;
      };
      const int grain_mat = material_of("grain_material"), binder_mat = material_of("binder_material");
      const std::string fields = spec_t->string("grain_fields", "colours");
      if (fields != "colours" && fields != "single") spec_t->fail("grain_fields", "must be 'colours' or 'single'");
      Packing packing;
      if (spec_t->has("packing_dir")) {
        if (spec_t->has("seed"))
          spec_t->fail("seed",
                       "has no effect with specimen.packing_dir (the packing is read from there, not generated): "
                       "remove one of the two");
        packing = read_packing(deck.resolve(spec_t->string("packing_dir")));
      } else {
        PackingSpec ps = read_packing_spec(root.table("packing"));
        if (spec_t->has("seed")) {
          const long seed = spec_t->integer("seed");
          if (seed < 0) spec_t->fail("seed", fmt::format("must be >= 0 (got {})", seed));
          ps.seed = static_cast<std::uint64_t>(seed);
        }
        packing = generate_packing(ps);
      }
      for (int d = 0; d < 2; ++d) {
        const double want = d == 0 ? sc.die->width : sc.die->height;
        if (std::abs(packing.box[d] - want) > 1e-9 * want)
          spec_t->fail("grain_material", fmt::format("the packing box ({} x {} m{}) differs from the die ({} x {} m)",
                                                     packing.box[0], packing.box[1],
                                                     packing.tiles[0] * packing.tiles[1] > 1
                                                         ? fmt::format(", packing.box times packing.tiles [{}, {}]",
                                                                       packing.tiles[0], packing.tiles[1])
                                                         : std::string(),
                                                     sc.die->width, sc.die->height));
      }
      // Grains whose TATB cores come within two cells of each other share grid nodes (two uGIMP
      // supports reach 2.5 cells, less the quarter cell each body's outer particles sit inside its
      // surface): on one velocity field they would move as one body, with no contact law between
      // them. The packing's colours respect only its contact_gap (2 um); where they put such
      // grains on one field, the grains are coloured again (a packing whose colours already hold
      // keeps them: at 2.5 um cells the paper specimens do). bspline2 supports reach 1.5 cells each,
      // so there the distance is 3 cells less the two outer particles' offsets (h / 2ppc each).
      if (fields == "colours" && packing.image.nx == 0) {
        const int before = packing.stats.colours;
        const double share_cells = sc.settings.kernel == Kernel::bspline2 ? 3.0 - 1.0 / ppc : 2.0;
        if (const int clashes = separate_colours_within(packing, share_cells * h); clashes > 0)
          if (notes == SceneNotes::print)
            fmt::print(
                stderr,
                "pbxmpm: note: {} of grains of one contact colour come{} within {:g} cells ({:.3g} m) of each "
                "other at this cell size and would share grid nodes (one body, no contact law): {}\n",
                clashes == 1 ? std::string("1 pair") : fmt::format("{} pairs", clashes), clashes == 1 ? "s" : "",
                share_cells, share_cells * h,
                packing.stats.colours == before
                    ? fmt::format("the grains re-coloured among the packing's {} colours", before)
                    : fmt::format("re-coloured with {} colours (the packing had {})", packing.stats.colours, before));
      }
      sc.packing_stats = packing.stats;
      if (packing.grains_shrunk > 0)
        if (notes == SceneNotes::print)
          fmt::print(
              stderr,
              "pbxmpm: note: the packer shrank {} grain{}, by up to {:.2g} % of the diameter, to remove the last "
              "overlaps (packing.json: grains_shrunk, max_relative_shrink)\n",
              packing.grains_shrunk, packing.grains_shrunk == 1 ? "" : "s", 100 * packing.max_shrink);
      const double specimen_particles = layers * sc.die->width * sc.die->height / std::pow(sub, 2);
      check_fits(
          gt, "cell_size", specimen_particles * kParticleBytes,
          fmt::format("the specimen's {:.3g} particles at this cell size and particles_per_cell", specimen_particles));
      auto field_of = [&](const std::string& fname) {
        auto [fit, inserted] = field_index.try_emplace(fname, static_cast<int>(field_index.size()));
        if (inserted) sc.field_names.push_back(fname);
        return fit->second;
      };
      const int binder_field = field_of(sc.material_names[binder_mat]);
      for (const ParticleSeed& seed : rasterise(packing, h, ppc, Eigen::Vector2d::Zero())) {
        const bool grain = seed.phase == 0;
        const int mat = grain ? grain_mat : binder_mat;
        const int fld =
            !grain ? binder_field
                   : field_of(fields == "single" ? sc.material_names[grain_mat]
                                                 : fmt::format("{}_{}", sc.material_names[grain_mat], seed.colour));
        const double volume = D == 3 ? seed.volume * sub : seed.volume;
        for (int k = 0; k < layers; ++k) {
          Vec<D> x;
          x[0] = seed.x[0], x[1] = seed.x[1];
          if constexpr (D == 3) x[2] = (k + 0.5) * sub;
          sc.particles.add(x, volume, volume * sc.materials[mat]->density(), mat, fld);
          sc.grain_coat.push_back(grain && seed.grain >= 0 ? packing.grains[static_cast<std::size_t>(seed.grain)].coat
                                                           : 0.0);
          sc.grain_index.push_back(grain ? seed.grain : -1);
        }
      }
      // The particles hold the packing to within their rasterisation: say when the specimen the
      // run computes misses the packing's porosity by more than the packer's default tolerance
      // (20 um cells: up to 0.0023 depending on where the grid falls).
      double solid = 0;
      for (std::size_t p = 0; p < sc.particles.size(); ++p) solid += sc.particles.volume0[p];
      const double phi = 1.0 - solid / sc.die->volume();
      if (std::abs(phi - packing.stats.porosity) > 0.002)
        if (notes == SceneNotes::print)
          fmt::print(
              stderr,
              "pbxmpm: note: the particle specimen's porosity {:.5f} differs from the packing's {:.5f} by {:+.5f} at "
              "this cell size (rasterisation); run.json's specimen.porosity and density are the particles'\n",
              phi, packing.stats.porosity, phi - packing.stats.porosity);
    }
  }

  // ---- geometry -> particles (first geometry containing a sub-cell centre wins)
  std::vector<DeckTable> geoms = root.tables("geometry");
  if (geoms.empty() && sc.particles.size() == 0)
    root.fail("geometry", "at least one [[geometry]] entry (or a [specimen]) is required");
  struct Geo {
    Shape<D> shape;
    int material, field;
    Vec<D> velocity;
  };
  std::vector<Geo> gs;
  Vec<D> lo = Vec<D>::Constant(1e300), hi = Vec<D>::Constant(-1e300);
  for (auto& g : geoms) {
    Geo geo;
    geo.shape = read_shape<D>(g);
    const std::string mname = g.string("material");
    auto it = mat_index.find(mname);
    if (it == mat_index.end()) g.fail("material", fmt::format("no material named '{}' in [materials]", mname));
    geo.material = it->second;
    const std::string fname = g.string("field", mname);
    auto [fit, inserted] = field_index.try_emplace(fname, static_cast<int>(field_index.size()));
    if (inserted) sc.field_names.push_back(fname);
    geo.field = fit->second;
    geo.velocity = read_vec<D>(g, "velocity", dim::velocity, Vec<D>::Zero());
    lo = lo.cwiseMin(geo.shape.lo);
    hi = hi.cwiseMax(geo.shape.hi);
    gs.push_back(std::move(geo));
  }
  sc.deformable_fields = static_cast<int>(sc.field_names.size());
  const double pvol = std::pow(h / ppc, D);
  if (!gs.empty()) {
    double box = 1;  // the geometry's bounding box, clipped to the grid: the most it can seed
    for (int d = 0; d < D; ++d) box *= std::max(0.0, std::min(hi[d], gmax[d]) - std::max(lo[d], gmin[d]));
    const double at_most = box / pvol;
    check_fits(root, "geometry", at_most * kParticleBytes,
               fmt::format("the [[geometry]] entries' up to {:.3g} particles (check their sizes and grid.cell_size)",
                           at_most));
  }
  std::vector<long> seeded(gs.size(), 0);
  int grain_count = 0;  // ids of the [[geometry]] bodies follow the packed grains'
  for (int gi : sc.grain_index) grain_count = std::max(grain_count, gi + 1);
  if (!gs.empty())
    seed_subcells<D>(sc.grid, ppc, lo, hi, [&](const Vec<D>& x) {
      for (std::size_t k = 0; k < gs.size(); ++k) {
        const Geo& g = gs[k];
        if (!g.shape.contains(x)) continue;
        const std::size_t p =
            sc.particles.add(x, pvol, pvol * sc.materials[g.material]->density(), g.material, g.field);
        sc.particles.v[p] = g.velocity;
        sc.grain_index.push_back(static_cast<int>(grain_count + k));  // bodies after any packed grains
        ++seeded[k];
        return;
      }
    });
  for (std::size_t k = 0; k < gs.size(); ++k)
    if (seeded[k] == 0)
      geoms[k].fail("shape",
                    "this entry produced no particles: it lies outside the grid, is thinner than a "
                    "particle spacing, or is covered by an earlier entry (the first entry containing a point wins)");
  // In a die the specimen must lie in the cavity: a body reaching into a wall or the punch would
  // start interpenetrated, and the contact would fling it out at the first step.
  if (sc.die)
    for (std::size_t k = 0; k < gs.size(); ++k) {
      const double W = sc.die->width, H = sc.die->height, tol = 1e-9 * std::max(W, H);
      const Shape<D>& sh = gs[k].shape;
      for (int d = 0; d < D; ++d) {
        const double top = d == 0 ? W : d == 1 ? H : sc.die->depth;
        if (sh.lo[d] < -tol || sh.hi[d] > top + tol)
          geoms[k].fail(geoms[k].string("shape", "rectangle") == "disk" ? "center"
                        : sh.lo[d] < -tol                               ? "min"
                                                                        : "max",
                        fmt::format("reaches outside the die cavity (0 to {} m in x, 0 to {} m in y{}): "
                                    "the walls and the punch would overlap it",
                                    W, H, D == 3 ? fmt::format(", 0 to {} m in z", sc.die->depth) : ""));
      }
    }
  if (sc.particles.size() == 0) root.fail("geometry", "the geometry entries produced no particles");

  // ---- rigid bodies: the die, then [[rigid]] entries
  // `shape`: the [[rigid]] entry's shape (a disk is filled as a disk, not as its bounding box);
  // none for the die's boxes.
  auto add_body = [&](RigidBody<D> b, const Vec<D>& blo, const Vec<D>& bhi, const Shape<D>* shape = nullptr) {
    b.field = sc.deformable_fields + static_cast<int>(sc.bodies.size());
    seed_subcells<D>(sc.grid, ppc, blo, bhi, [&](const Vec<D>& x) {
      bool in = true;
      for (int d = 0; d < D; ++d) in = in && x[d] > blo[d] && x[d] < bhi[d];
      if (in && (!shape || shape->contains(x))) b.x0.push_back(x);
    });
    if (b.x0.empty())
      throw InputError(
          fmt::format("rigid body '{}' holds no rigid particle (smaller than a particle spacing of the grid)", b.name));
    b.x = b.x0;
    b.face0 = -1e300;
    for (auto& x : b.x0) b.face0 = std::max(b.face0, x.dot(b.normal) + 0.5 * h / ppc);
    sc.field_names.push_back(b.name);
    sc.bodies.push_back(std::move(b));
    return static_cast<int>(sc.bodies.size()) - 1;
  };
  if (sc.die) {
    // the walls (wall_cells thick) hold the cavity [0, W] x [0, H] (x [0, Dz] in 3-D) on every side
    // but the top, where the punch sits; in 3-D the left and right walls span the whole depth and
    // the front and back walls fit between them
    Die& die = *sc.die;
    const double wt = wall_cells * h, W = die.width, H = die.height, Dz = die.depth;
    const double mu = die_t->non_negative("wall_friction", dim::none, 0.0);
    const double cutoff = die_t->non_negative("contact_cutoff", dim::none, 0.8);
    // a box from its x and y ranges (and, in 3-D, its z range)
    const auto corner = [](double x, double y, double z) {
      Vec<D> v;
      v[0] = x, v[1] = y;
      if constexpr (D == 3) v[2] = z;
      return v;
    };
    const double z0 = -wt, z1 = Dz + wt;
    auto wall = [&](const char* name, Vec<D> n, Vec<D> blo, Vec<D> bhi) {
      RigidBody<D> b;
      b.name = name;
      b.normal = n;
      b.friction = mu;
      b.cutoff = cutoff;
      return add_body(std::move(b), blo, bhi);
    };
    die.left = wall("wall_left", corner(1, 0, 0), corner(-wt, -wt, z0), corner(0, H + wt, z1));
    die.right = wall("wall_right", corner(-1, 0, 0), corner(W, -wt, z0), corner(W + wt, H + wt, z1));
    die.bottom = wall("wall_bottom", corner(0, 1, 0), corner(0, -wt, 0), corner(W, 0, Dz));
    if constexpr (D == 3) {
      die.front = wall("wall_front", corner(0, 0, 1), corner(0, -wt, -wt), corner(W, H + wt, 0));
      die.back = wall("wall_back", corner(0, 0, -1), corner(0, -wt, Dz), corner(W, H + wt, Dz + wt));
    }
    RigidBody<D> punch;
    punch.name = "punch";
    punch.normal = corner(0, -1, 0);
    punch.friction = mu;
    punch.cutoff = cutoff;
    punch.velocity = corner(0, -die.punch_velocity, 0);
    punch.ramp.t_ramp = die.ramp_time();
    die.punch = add_body(std::move(punch), corner(0, H, 0), corner(W, H + wt, Dz));
  }
  for (auto& r : root.tables("rigid")) {
    RigidBody<D> b;
    b.name = r.string("name");
    // the name labels history columns and a velocity field: it must not be another field's
    if (std::find(sc.field_names.begin(), sc.field_names.end(), b.name) != sc.field_names.end())
      r.fail("name", fmt::format("'{}' is already the name of a field or body (die bodies: wall_left, wall_right, "
                                 "wall_bottom, punch; in 3-D also wall_front, wall_back)",
                                 b.name));
    const Shape<D> s = read_shape<D>(r);
    b.normal = read_vec<D>(r, "normal", dim::none);
    const std::string c = r.string("contact", "unilateral");
    if (c == "stick")
      b.contact = RigidContact::stick;
    else if (c != "unilateral")
      r.fail("contact", "unknown rigid contact '" + c + "' (known: unilateral, stick)");
    if (std::abs(b.normal.norm() - 1.0) > 1e-9) r.fail("normal", "must be a unit vector (outward, into the specimen)");
    b.friction = r.non_negative("friction", dim::none, 0.0);
    b.cutoff = r.non_negative("contact_cutoff", dim::none, 0.8);
    b.velocity = read_vec<D>(r, "velocity", dim::velocity, Vec<D>::Zero());
    b.ramp.t_ramp = r.non_negative("ramp_time", dim::time, 0.0);
    // A unilateral body that starts over deformable particles pushes out (or carries) the
    // particles it covers from the first step. Said, not refused: a test deck uses a plate
    // over the upper half of a disk as the disk's symmetry plane (tests/contact/test_hertz.cpp).
    if (b.contact == RigidContact::unilateral) {
      std::size_t covered = 0, first = 0;
      for (std::size_t p = 0; p < sc.particles.size(); ++p) {
        const Vec<D>& x = sc.particles.x[p];
        bool in = s.contains(x);
        for (int d = 0; d < D; ++d) in = in && x[d] > s.lo[d] && x[d] < s.hi[d];
        if (in && covered++ == 0) first = p;
      }
      if (covered > 0)
        if (notes == SceneNotes::print)
          fmt::print(
              stderr,
              "pbxmpm: warning: {}: rigid body '{}' starts over {} deformable particle{} (the first: particle {} "
              "of material '{}'); a unilateral body pushes them out or carries them from the first step\n",
              r.where("min"), b.name, covered, covered == 1 ? "" : "s", first,
              sc.material_names[sc.particles.material[first]]);
    }
    add_body(std::move(b), s.lo, s.hi, &s);
  }

  // ---- every particle must sit where its whole stencil is inside the grid
  auto check_inside = [&](const Vec<D>& x, const std::string& what) {
    for (int d = 0; d < D; ++d) {
      const double s = (x[d] - sc.grid.origin[d]) / h;
      if (!(s >= 1.0 && s < static_cast<double>(sc.grid.n[d]) - 2.0))
        throw InputError(
            fmt::format("{} at ({}) m lies outside the grid interior: {}", what,
                        fmt::join(std::vector<double>(x.data(), x.data() + D), ", "),
                        sc.die ? "keep [[rigid]] bodies within die.wall_cells of the die" : "enlarge [grid] min/max"));
    }
  };
  for (std::size_t p = 0; p < sc.particles.size(); ++p)
    check_inside(sc.particles.x[p],
                 fmt::format("particle {} (material '{}')", p, sc.material_names[sc.particles.material[p]]));
  for (auto& b : sc.bodies)
    for (auto& x : b.x0) check_inside(x, "a particle of rigid body '" + b.name + "'");

  // ---- material batches and history
  sc.material_state.resize(sc.materials.size());
  for (std::size_t p = 0; p < sc.particles.size(); ++p) {
    auto& st = sc.material_state[static_cast<std::size_t>(sc.particles.material[p])];
    sc.particles.slot[p] = static_cast<std::uint32_t>(st.index.size());
    st.index.push_back(static_cast<std::uint32_t>(p));
  }
  for (std::size_t m = 0; m < sc.materials.size(); ++m) {
    const int hs = sc.materials[m]->history_size();
    auto& st = sc.material_state[m];
    st.history.assign(st.index.size() * static_cast<std::size_t>(hs), 0.0);
    for (std::size_t k = 0; k < st.index.size(); ++k) sc.materials[m]->init_history(st.history.data() + k * hs);
  }

  // ---- storage order: strip by strip (the solver's scatter strips)
  order_by_strip(sc);

  // ---- contact between deformable fields (issue 4): laws per pair of materials
  {
    std::vector<int> field_material(static_cast<std::size_t>(sc.deformable_fields), -2);
    for (std::size_t p = 0; p < sc.particles.size(); ++p) {
      int& fm = field_material[static_cast<std::size_t>(sc.particles.field[p])];
      fm = (fm == -2 || fm == sc.particles.material[p]) ? sc.particles.material[p] : -1;  // -1: mixed
    }
    sc.contact = read_contact_matrix(root.optional_table("contact"), field_material, sc.material_names);
    if (extruded_specimen) sc.contact.extruded_axis = 2;
    setup_binder_layers(sc, root);
    if (sc.layer_data.gap_particles_joined > 0 && notes == SceneNotes::print)
      fmt::print(stderr,
                 "pbxmpm: note: gap_binder = \"join\": {} particles of the binder lying in bonded gaps joined the "
                 "field of their nearer grain (the film carries that binder; docs/theory/contact.md)\n",
                 sc.layer_data.gap_particles_joined);
    std::vector<double>().swap(sc.grain_coat);  // only the layers' setup reads these
    std::vector<int>().swap(sc.grain_index);
  }

  // Rigid contact bodies (the die, unilateral [[rigid]]) meet the specimen at grid nodes. Measured on the elastic
  // column in the die (tests/engine/test_die_block.cpp, 10 and 5 um cells): uGIMP passes (confined modulus within
  // 1 %, wall/punch within 2 %); bspline2 passes once its basis is clamped at the die's walls and floor (fixed node
  // lines, grid/shape.hpp; unclamped the wall/punch ratio was 7 % and M 1.4 % low), which leaves the punch and any
  // [[rigid]] face unclamped (the punch's share of M's error: about 0.4 %); with linear shapes the particles in front
  // of a face lying between nodes move slower than the face, the top row is overrun and the run inverts a particle
  // (at 1.5 % strain with 10 um cells, for every contact_cutoff from 0 to 1; M 15 % low before), the cell-crossing
  // error of the linear hat. A face contact that keeps the top row in front of the punch does not save it: the
  // column's mean strain then falls 24 % short at 3.6 % (M 32 % low) from cell crossings in the bulk
  // (docs/theory/engine.md). Linear stays for runs without contact bodies (bar vibration with a stick clamp).
  bool die_only = true;  // every unilateral body is one of the die's
  for (std::size_t b = 0; b < sc.bodies.size(); ++b) {
    const int ib = static_cast<int>(b);
    if (sc.bodies[b].contact != RigidContact::stick && !(sc.die && sc.die->owns(ib))) die_only = false;
  }
  const bool unilateral = std::any_of(sc.bodies.begin(), sc.bodies.end(),
                                      [](const RigidBody<D>& b) { return b.contact != RigidContact::stick; });
  if (unilateral && sc.settings.kernel == Kernel::linear)
    gt.fail("shape_function",
            "'linear' is refused in a run with rigid contact bodies (a [die], or a [[rigid]] body that is not "
            "\"stick\"): the punch overruns the top particle row and the run inverts a particle (the linear hat's "
            "cell-crossing error); use \"ugimp\" or \"bspline2\", see docs/deck/engine.md");
  if (unilateral && sc.settings.kernel == Kernel::bspline2 && !die_only)
    gt.fail("shape_function",
            "'bspline2' is refused beside a unilateral [[rigid]] body: its basis is clamped only at the die's fixed "
            "walls, and a face elsewhere is not verified (unclamped, the die column's wall/punch ratio was 7 % low); "
            "use \"ugimp\", see docs/deck/engine.md");
  if (sc.die && sc.settings.kernel == Kernel::bspline2) {
    // the die's walls and floor lie on node lines (width and height are whole cells, the grid starts
    // wall_cells + 2 cells outside them)
    const int first = wall_cells + 2;
    sc.grid.clamped.lo[0] = first;
    sc.grid.clamped.hi[0] = first + static_cast<int>(std::lround(sc.die->width / h));
    sc.grid.clamped.lo[1] = first;
    if constexpr (D == 3) {
      sc.grid.clamped.lo[2] = first;
      sc.grid.clamped.hi[2] = first + static_cast<int>(std::lround(sc.die->depth / h));
    }
  }
  check_fits(
      gt, "cell_size",
      static_cast<double>(sc.grid.nodes()) *
          ((kGridBytesPerNodeField + (sc.contact.has_layers() ? kLayerBytesPerNodeField : 0.0)) * sc.deformable_fields +
           8.0 * static_cast<double>(sc.bodies.size())),
      fmt::format("the grid's {} nodes with {} velocity fields", sc.grid.nodes(), sc.deformable_fields));
  sc.grid.allocate(sc.deformable_fields, static_cast<int>(sc.bodies.size()));
  if (sc.contact.has_layers()) sc.layer_data.sums.allocate(sc.grid.mass.size());
  return sc;
}

template Scene<2> build_scene<2>(const Deck&, SceneNotes);
template Scene<3> build_scene<3>(const Deck&, SceneNotes);

}  // namespace pbx
