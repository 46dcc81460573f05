// The first brick of one run over many ranks (issue 28; docs/architecture.md, "One run over many
// ranks"): the strips shared out over ranks, a rank's part of a scene, and the parity exchange,
// whose nodal sums on 2 and 3 ranks must equal one process's to the bit on the paper specimen.
// The MPI test launches itself under mpirun (each rank runs the test's MPI part).
#include <mpi.h>

#include <cstdlib>
#include <algorithm>
#include <cstring>
#include <memory>
#include <fstream>
#include <sstream>
#include <string>
#include <tuple>
#include <vector>

#include <fmt/format.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include "core/error.hpp"
#include "distributed/strip_exchange.hpp"
#include "distributed/strip_partition.hpp"
#include "io/deck.hpp"
#include "io/deck_override.hpp"
#include "setup/build_scene.hpp"
#include "solver/solver.hpp"

using namespace pbx;

namespace {

// The quick study's paper specimen (20 um cells, 293 K, porosity 0.08, seed 1): its grains on the
// fields of their contact colours and the binder field, binder-layer sums on; `kernel` as the deck
// spells it.
// `tiles` copies of the packed cell along x in a die as many times wider (packing.tiles).
Scene<2> paper_specimen(const std::string& kernel, int tiles = 1) {
  const std::string dir = std::string(PBXMPM_EXAMPLES_DIR) + "/paper", file = dir + "/base.toml";
  std::ifstream in(file);
  std::stringstream ss;
  ss << in.rdbuf();
  std::vector<DeckOverride> set = {{"grid.cell_size", "\"20 um\""},
                                   {"grid.shape_function", "\"" + kernel + "\""},
                                   {"packing.porosity", "0.08"},
                                   {"run.temperature", "\"293 K\""},
                                   {"specimen.seed", "1"}};
  if (tiles > 1) {
    set.emplace_back("packing.tiles", fmt::format("[{}, 1]", tiles));
    set.emplace_back("die.width", fmt::format("\"{} mm\"", tiles));
  }
  Deck deck = Deck::from_string(deck_with_overrides(ss.str(), file, set), file, dir);
  return build_scene<2>(deck, SceneNotes::quiet);
}

bool under_mpirun() { return std::getenv("OMPI_COMM_WORLD_SIZE") != nullptr; }

// Runs this executable's test `name` under mpirun with 2 and with 3 ranks and expects every rank to
// pass it (the test's MPI part runs when the process finds itself under mpirun).
void run_under_mpirun(const std::string& name) {
  if (std::system("command -v mpirun > /dev/null 2>&1") != 0) GTEST_SKIP() << "mpirun not installed";
  char self[4096] = {};
  ASSERT_GT(::readlink("/proc/self/exe", self, sizeof self - 1), 0);
  for (int n : {2, 3}) {
    const std::string line = fmt::format(
        "OMP_NUM_THREADS=1 timeout 150 mpirun --allow-run-as-root --oversubscribe --bind-to none -n {} '{}' "
        "--gtest_color=no --gtest_filter={} 2>&1",
        n, self, name);
    FILE* p = popen(line.c_str(), "r");
    ASSERT_NE(p, nullptr);
    std::string out;
    char buf[4096];
    std::size_t k;
    while ((k = fread(buf, 1, sizeof buf, p)) > 0) out.append(buf, k);
    const int status = pclose(p);
    EXPECT_EQ(status, 0) << n << " ranks:\n" << out;
    int passed = 0;
    for (auto at = out.find("[  PASSED  ] 1 test"); at != std::string::npos;
         at = out.find("[  PASSED  ] 1 test", at + 1))
      ++passed;
    EXPECT_EQ(passed, n) << out;
  }
}

// MPI for a test's part under mpirun (one test per process): joined here, left at the end.
struct MpiScope {
  int rank = 0, size = 1;
  MpiScope() {
    MPI_Init(nullptr, nullptr);
    MPI_Comm_rank(MPI_COMM_WORLD, &rank);
    MPI_Comm_size(MPI_COMM_WORLD, &size);
  }
  ~MpiScope() { MPI_Finalize(); }
  MpiScope(const MpiScope&) = delete;
  MpiScope& operator=(const MpiScope&) = delete;
};

// This rank's part of the paper specimen, its exchange and its solver, beside the whole scene's.
struct RankRun {
  Scene<2> whole, mine;
  Solver<2> one;
  StripPartition part;
  long first = 0, end = 0;
  std::unique_ptr<StripExchange<2>> exchange;
  std::unique_ptr<Solver<2>> local;
  RankRun(const std::string& kernel, int rank, int size)
      : whole(paper_specimen(kernel)), mine(paper_specimen(kernel)), one(whole) {
    const std::vector<long>& sb = one.strips().begin;
    part = partition_strips(sb, size);
    first = part.first[static_cast<std::size_t>(rank)];
    end = part.first[static_cast<std::size_t>(rank) + 1];
    keep_particle_range(mine, static_cast<std::size_t>(sb[static_cast<std::size_t>(first)]),
                        static_cast<std::size_t>(sb[static_cast<std::size_t>(end)]));
    local = std::make_unique<Solver<2>>(mine);
    exchange =
        std::make_unique<StripExchange<2>>(MPI_COMM_WORLD, mine.grid, &mine.layer_data.sums, one.strips().width,
                                           one.strips().strips, first, end, mine.settings.kernel != Kernel::linear);
    local->set_scatter_exchange(exchange.get(), one.mass_threshold());
  }
  std::size_t offset() const { return static_cast<std::size_t>(one.strips().begin[static_cast<std::size_t>(first)]); }
};

}  // namespace

// Whole strips, contiguous, every rank its minimum, and the particles shared within a strip's worth.
TEST(StripPartition, SharesWholeStripsBalancedByParticles) {
  // 10 strips of 100 particles, one of 1,000
  std::vector<long> begin = {0};
  for (int s = 0; s < 11; ++s) begin.push_back(begin.back() + (s == 4 ? 1000 : 100));
  const StripPartition two = partition_strips(begin, 2);
  ASSERT_EQ(two.first.size(), 3u);
  EXPECT_EQ(two.first[0], 0);
  EXPECT_EQ(two.first[2], 11);
  // half of 2,000 particles is reached at the end of strip 4 (1,400 >= 1,000)
  EXPECT_EQ(two.first[1], 5);
  const StripPartition four = partition_strips(begin, 4, 2);
  for (int r = 0; r < 4; ++r) EXPECT_GE(four.strips_of(r), 2) << r;
  EXPECT_EQ(four.first.back(), 11);
  EXPECT_THROW(partition_strips(begin, 4, 3), std::invalid_argument);  // 11 strips cannot give 12
  EXPECT_THROW(partition_strips(begin, 0), std::invalid_argument);
}

// The weak-scaling specimen (docs/performance/engine.md): the paper specimen's packed cell twice
// side by side is the cell's particles twice, the second copy shifted by the cell's width, with the
// same fields, and two ranks' halves of it each hold exactly the cell's particles: the same work per
// rank as the one-process run of the cell.
TEST(StripPartition, TiledPaperSpecimenGivesEachOfTwoRanksTheCellsParticles) {
  const Scene<2> cell = paper_specimen("ugimp"), two = paper_specimen("ugimp", 2);
  const auto& C = cell.particles;
  const auto& T = two.particles;
  ASSERT_EQ(T.size(), 2 * C.size());
  EXPECT_EQ(two.deformable_fields, cell.deformable_fields);
  using Key = std::tuple<int, double, double, double, double>;  // material, x, y, volume, mass
  auto keys = [](const Particles<2>& P, double x_lo, double x_hi, double shift) {
    std::vector<Key> k;
    for (std::size_t p = 0; p < P.size(); ++p)
      if (P.x[p][0] >= x_lo && P.x[p][0] < x_hi)
        k.emplace_back(P.material[p], P.x[p][0] - shift, P.x[p][1], P.volume0[p], P.mass[p]);
    std::sort(k.begin(), k.end());
    return k;
  };
  const auto c = keys(C, 0, 1e-3, 0);
  ASSERT_EQ(c.size(), C.size());
  for (int copy = 0; copy < 2; ++copy) {
    const auto t = keys(T, copy * 1e-3, (copy + 1) * 1e-3, copy * 1e-3);
    ASSERT_EQ(t.size(), c.size()) << copy;
    for (std::size_t i = 0; i < c.size(); ++i) {
      EXPECT_EQ(std::get<0>(t[i]), std::get<0>(c[i]));
      EXPECT_NEAR(std::get<1>(t[i]), std::get<1>(c[i]), 1e-15) << copy << " " << i;
      EXPECT_EQ(std::get<2>(t[i]), std::get<2>(c[i]));
      EXPECT_DOUBLE_EQ(std::get<3>(t[i]), std::get<3>(c[i]));
      EXPECT_DOUBLE_EQ(std::get<4>(t[i]), std::get<4>(c[i]));
    }
  }
  Scene<2> copy = paper_specimen("ugimp", 2);
  const Solver<2> solver(copy);
  const auto& sb = solver.strips().begin;
  const StripPartition part = partition_strips(sb, 2);
  EXPECT_EQ(sb[static_cast<std::size_t>(part.first[1])], static_cast<long>(C.size()));
}

// A tiled packing in a die that was not widened is refused, and the message says the box was tiled.
TEST(StripPartition, TiledPackingInANarrowDieIsRefusedNamingTheTiles) {
  const std::string dir = std::string(PBXMPM_EXAMPLES_DIR) + "/paper", file = dir + "/base.toml";
  std::ifstream in(file);
  std::stringstream ss;
  ss << in.rdbuf();
  const std::vector<DeckOverride> set = {{"grid.cell_size", "\"20 um\""}, {"packing.tiles", "[2, 1]"}};
  Deck deck = Deck::from_string(deck_with_overrides(ss.str(), file, set), file, dir);
  try {
    build_scene<2>(deck, SceneNotes::quiet);
    FAIL() << "a 2 mm packing in a 1 mm die was accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("packing.box times packing.tiles [2, 1]) differs from the die"),
              std::string::npos)
        << e.what();
  }
}

// Each rank's part of the scene, taken after the whole scene was set up, holds the whole scene's
// particles of its strips with their history rows and binder-layer data, in the same order.
TEST(KeepParticleRange, TheRanksPartsTogetherAreTheWholeScene) {
  Scene<2> whole = paper_specimen("ugimp");
  Solver<2> solver(whole);
  const std::vector<long> sb = solver.strips().begin;
  const StripPartition part = partition_strips(sb, 3);
  std::size_t total = 0;
  for (int r = 0; r < 3; ++r) {
    Scene<2> sc = paper_specimen("ugimp");
    const auto b = static_cast<std::size_t>(sb[static_cast<std::size_t>(part.first[static_cast<std::size_t>(r)])]);
    const auto e = static_cast<std::size_t>(sb[static_cast<std::size_t>(part.first[static_cast<std::size_t>(r) + 1])]);
    keep_particle_range(sc, b, e);
    ASSERT_EQ(sc.particles.size(), e - b);
    total += sc.particles.size();
    // every kept particle in its material's batch once, every batch with its history rows
    std::size_t in_batches = 0;
    for (std::size_t m = 0; m < sc.material_state.size(); ++m) {
      in_batches += sc.material_state[m].index.size();
      EXPECT_EQ(sc.material_state[m].history.size(),
                sc.material_state[m].index.size() * static_cast<std::size_t>(sc.materials[m]->history_size()));
    }
    EXPECT_EQ(in_batches, sc.particles.size());
    for (std::size_t p = 0; p < sc.particles.size(); ++p) {
      ASSERT_EQ(sc.particles.x[p], whole.particles.x[b + p]) << p;
      ASSERT_EQ(sc.particles.v[p], whole.particles.v[b + p]);
      ASSERT_EQ(sc.particles.mass[p], whole.particles.mass[b + p]);
      ASSERT_EQ(sc.particles.volume0[p], whole.particles.volume0[b + p]);
      ASSERT_EQ(sc.particles.F[p], whole.particles.F[b + p]);
      ASSERT_EQ(sc.particles.stress[p].xx, whole.particles.stress[b + p].xx);
      ASSERT_EQ(sc.layer_data.particles.N0[p], whole.layer_data.particles.N0[b + p]);
      ASSERT_EQ(sc.layer_data.particles.inv_t[p], whole.layer_data.particles.inv_t[b + p]);
      ASSERT_EQ(sc.particles.material[p], whole.particles.material[b + p]);
      ASSERT_EQ(sc.particles.field[p], whole.particles.field[b + p]);
      ASSERT_EQ(sc.layer_data.particles.bonded[p], whole.layer_data.particles.bonded[b + p]);
      ASSERT_EQ(sc.layer_data.particles.X0[p], whole.layer_data.particles.X0[b + p]);
      // the particle's history row is the whole scene's row of the same particle
      const std::size_t m = static_cast<std::size_t>(sc.particles.material[p]);
      const std::size_t hs = static_cast<std::size_t>(sc.materials[m]->history_size());
      ASSERT_EQ(sc.material_state[m].index[sc.particles.slot[p]], p);
      for (std::size_t i = 0; i < hs; ++i)
        ASSERT_EQ(sc.material_state[m].history[sc.particles.slot[p] * hs + i],
                  whole.material_state[m].history[whole.particles.slot[b + p] * hs + i]);
    }
  }
  EXPECT_EQ(total, whole.particles.size());
  EXPECT_GT(whole.layer_data.particles.bonded.size(), 0u) << "the specimen should have binder layers";
}

// The parity exchange: the first P2G of the paper specimen split over 2 and 3 ranks gives at every
// node a rank's particles reach the one-process sums to the bit (mass, momentum, force, offsets,
// volume gradients and the binder-layer sums, every field), for uGIMP and bspline2 (clamped at the
// die). Adding the two ranks' partial sums instead would differ in the last bits at the shared
// lines; this test would see it.
TEST(StripExchange, RanksGiveTheOneProcessNodalSumsToTheBit) {
  if (!under_mpirun()) return run_under_mpirun("StripExchange.RanksGiveTheOneProcessNodalSumsToTheBit");
  const MpiScope mpi;
  const int rank = mpi.rank, size = mpi.size;
  for (const char* kernel : {"ugimp", "bspline2"}) {
    RankRun run(kernel, rank, size);
    run.one.reset_grid();
    run.one.p2g(true);
    run.local->reset_grid();
    run.local->p2g(true);
    const Scene<2>& whole = run.whole;
    const Scene<2>& mine = run.mine;
    const StripBins& bins = run.one.strips();
    const long first = run.first, end = run.end;

    // the node lines this rank's particles reach
    const Grid<2>& a = whole.grid;
    const Grid<2>& b = mine.grid;
    const long lo = first == 0 ? 0 : first * bins.width - 1;
    const long hi = end == bins.strips ? a.n[0] - 1 : end * bins.width + 1;
    long compared = 0, differ = 0, shared_nonzero = 0;
    const auto same = [&](const double* x, const double* y, int w) {
      return std::memcmp(x, y, sizeof(double) * w) == 0;
    };
    for (int f = 0; f < a.deformable; ++f)
      for (long j = 0; j < a.n[1]; ++j)
        for (long i = lo; i <= hi; ++i) {
          const auto k = static_cast<std::size_t>(a.at(f, i + j * a.stride[1]));
          bool ok = same(&a.mass[k], &b.mass[k], 1) && same(a.mom[k].data(), b.mom[k].data(), 2) &&
                    same(a.force[k].data(), b.force[k].data(), 2) && same(a.moff[k].data(), b.moff[k].data(), 2) &&
                    same(a.vgrad[k].data(), b.vgrad[k].data(), 2);
          const auto& la = whole.layer_data.sums;
          const auto& lb = mine.layer_data.sums;
          ok = ok && same(la.mref[k].data(), lb.mref[k].data(), 2) && same(la.mdef[k].data(), lb.mdef[k].data(), 4) &&
               same(&la.mbond[k], &lb.mbond[k], 1) && same(la.mnorm[k].data(), lb.mnorm[k].data(), 2) &&
               same(&la.minvt[k], &lb.minvt[k], 1);
          ++compared;
          differ += !ok;
          const bool shared = (first > 0 && i <= lo + 2) || (end < bins.strips && i >= hi - 2);
          shared_nonzero += shared && a.mass[k] > 0;
        }
    EXPECT_EQ(differ, 0) << kernel << ": rank " << rank << " of " << size << ", " << compared << " node-fields";
    // the shared lines hold mass (the test compares sums two ranks made, not empty nodes)
    if (size > 1) {
      EXPECT_GT(shared_nonzero, 50) << kernel << ": rank " << rank;
    }
  }
}

// A few hundred USL steps of the paper specimen from rest (the punch ramp under way, the binder
// layers' springs acting) on 2 and 3 ranks: every rank's particles end with the one-process run's
// positions, velocities, stresses, deformation gradients and history to the bit, and every step
// took the one-process time step; and every rank holds the one-process run's sums over nodes and
// particles to the bit (stress work, dissipation and its parts, friction, the springs' energy, the
// kinetic energy, the rigid bodies' impulses and work, the contact tally): each rank makes the parts
// of its strips, and the parts are summed in strip order (StripBins::fold).
TEST(StripExchange, RanksStepTheOneProcessDynamicsToTheBit) {
  if (!under_mpirun()) return run_under_mpirun("StripExchange.RanksStepTheOneProcessDynamicsToTheBit");
  const MpiScope mpi;
  const int rank = mpi.rank, size = mpi.size;
  {
    RankRun run("ugimp", rank, size);
    const int steps = 400;
    long dt_differ = 0;
    for (int k = 0; k < steps; ++k) {
      run.one.step();
      run.local->step();
      dt_differ += run.one.dt() != run.local->dt();
    }
    EXPECT_EQ(dt_differ, 0) << "steps whose time step differs";
    // the books' sums of the last steps (the earlier ones were settled every 256 sums on the way)
    run.local->settle_books();
    const auto& A = run.whole.particles;
    const auto& B = run.mine.particles;
    const std::size_t o = run.offset();
    long differ = 0;
    const auto same = [](const auto& x, const auto& y) { return std::memcmp(&x, &y, sizeof x) == 0; };
    for (std::size_t p = 0; p < B.size(); ++p) {
      const bool ok = same(A.x[o + p], B.x[p]) && same(A.v[o + p], B.v[p]) && same(A.F[o + p], B.F[p]) &&
                      same(A.stress[o + p], B.stress[p]) && same(A.volume[o + p], B.volume[p]);
      differ += !ok;
    }
    EXPECT_EQ(differ, 0) << "rank " << rank << " of " << size << ": particles unlike the one-process run's, of "
                         << B.size();
    // the particles moved: the comparison is of a deformed state
    double vmax = 0;
    for (const auto& v : B.v) vmax = std::max(vmax, v.norm());
    EXPECT_GT(vmax, 1e-3) << "rank " << rank;
    // the sums the history reports
    const auto a = run.one.state(), b = run.local->state();
    EXPECT_TRUE(same(a.internal, b.internal) && same(a.dissipated, b.dissipated) && same(a.friction, b.friction))
        << "rank " << rank << ": stress work " << a.internal << " / " << b.internal << ", dissipated " << a.dissipated
        << " / " << b.dissipated << ", friction " << a.friction << " / " << b.friction;
    EXPECT_EQ(a.dissipated_by_material, b.dissipated_by_material) << "rank " << rank;
    EXPECT_GT(a.friction, 0.0);  // the contact sums are not all zero
    const double ke_a = run.one.kinetic_energy(), ke_b = run.local->kinetic_energy();
    const double le_a = run.one.layer_energy(), le_b = run.local->layer_energy();
    EXPECT_TRUE(same(ke_a, ke_b) && same(le_a, le_b))
        << "rank " << rank << ": kinetic " << ke_a << " / " << ke_b << ", springs " << le_a << " / " << le_b;
    EXPECT_GT(le_a, 0.0);
    for (std::size_t k = 0; k < run.whole.bodies.size(); ++k) {
      const auto &ba = run.whole.bodies[k], &bb = run.mine.bodies[k];
      EXPECT_TRUE(same(ba.impulse, bb.impulse) && same(ba.work, bb.work))
          << "rank " << rank << ", body " << k << ": impulse " << ba.impulse.transpose() << " / "
          << bb.impulse.transpose();
    }
    EXPECT_GT(run.whole.bodies.at(0).impulse.norm(), 0.0);
    const auto &ta = run.one.contact_tally().pair, &tb = run.local->contact_tally().pair;
    ASSERT_EQ(ta.size(), tb.size());
    long pairs_differ = 0;
    for (std::size_t k = 0; k < ta.size(); ++k)
      pairs_differ +=
          !(same(ta[k].on_first, tb[k].on_first) && same(ta[k].normal, tb[k].normal) && same(ta[k].shear, tb[k].shear));
    EXPECT_EQ(pairs_differ, 0) << "rank " << rank << ": pairs of fields whose contact impulses differ";
    // history rows (plastic strain, Prony internal variables) of this rank's particles
    for (std::size_t m = 0; m < run.mine.material_state.size(); ++m) {
      const std::size_t hs = static_cast<std::size_t>(run.mine.materials[m]->history_size());
      for (std::size_t p = 0; p < B.size(); ++p) {
        if (static_cast<std::size_t>(B.material[p]) != m) continue;
        for (std::size_t i = 0; i < hs; ++i)
          ASSERT_TRUE(same(run.mine.material_state[m].history[B.slot[p] * hs + i],
                           run.whole.material_state[m].history[A.slot[o + p] * hs + i]))
              << "rank " << rank << " particle " << p;
      }
    }
  }
}
