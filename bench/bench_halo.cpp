// The measurements behind the scaling model of a decomposition of one run over MPI ranks (issue 28;
// docs/performance/engine.md, "A scaling model for one run over many ranks"): what a decomposition
// moves, what moving it costs, and the decomposed step as far as it is built.
//  1. Halo census, on the paper specimen (examples/paper/base.toml, 293 K, phi = 0.08, seed 1) at
//     each cell size given, stepped `steps` steps: the node-fields holding mass on the three node
//     lines that two neighbouring domains share across a cut (a particle stencil reaches one node
//     line below its cell and two above, so the scatter's sums there are partial on both sides),
//     for cuts between the scatter strips (x) and for cuts along rows (y, a tile decomposition).
//     Also the wall time per particle-update of the whole step at one thread, and the strays.
//  2. Exchange timing (needs 2 ranks: mpirun -n 2): MPI_Sendrecv between ranks 0 and 1 of
//     messages of 8 B to 16 MB, each both ways at once as a halo exchange is, best of 3 rounds;
//     the fit t = alpha + bytes / beta (least squares, Eigen); and the exchange of each census's
//     own halo bytes, timed.
//  3. The decomposed USL step as built: the specimen stepped by one process, then split over every
//     rank (issue 28's built part; a stray stops it), wall time and parallel efficiency.
//  4. The model: time per step of one rank = its particles x the measured time per particle-update
//     + the exchanges (docs/performance/engine.md gives the protocol it assumes), predicted for
//     slab and tile decompositions of the 2-D full resolution, the 0.6 um resolution and a 3-D
//     specimen, at 16 to 1,024 ranks, with this machine's alpha and beta and with a cluster's
//     (--alpha US --beta GB/s; default 1.5 us and 12 GB/s, an EDR InfiniBand link).
// Usage: [mpirun -n 2] bench_halo [--cells 20,10,5] [--steps 50] [--timed 100] [--alpha us] [--beta GB/s]
#include <mpi.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include <Eigen/Dense>
#include <fmt/format.h>
#include <omp.h>

#include "io/deck.hpp"
#include "io/deck_override.hpp"
#include "distributed/strip_exchange.hpp"
#include "distributed/strip_partition.hpp"
#include "setup/build_scene.hpp"
#include "solver/solver.hpp"

using namespace pbx;

namespace {

struct Census {
  double cell_um = 0;
  long particles = 0, nx = 0, ny = 0, strip_width = 0, strays = 0;
  double slab_node_fields = 0;  // mean node-fields with mass on the 3 shared columns of an x-cut
  double row_node_fields = 0;   // mean node-fields with mass on 3 shared rows, per node along the row
  double bytes_per_node_field = 0;
  double ns_per_update = 0;  // whole step, one thread
};

std::string read_file(const std::string& file) {
  std::ifstream in(file);
  if (!in) throw std::runtime_error("cannot read " + file);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

Scene<2> specimen_scene(double cell_um) {
  const std::string dir = PBXMPM_SOURCE_DIR "/examples/paper";
  const std::string file = dir + "/base.toml";
  const std::vector<DeckOverride> set = {{"grid.cell_size", fmt::format("\"{} um\"", cell_um)},
                                         {"packing.porosity", "0.08"},
                                         {"run.temperature", "\"293 K\""},
                                         {"specimen.seed", "1"}};
  Deck deck = Deck::from_string(deck_with_overrides(read_file(file), file, set), file, dir);
  return build_scene<2>(deck, SceneNotes::quiet);
}

Census census(double cell_um, int steps, int timed) {
  Scene<2> sc = specimen_scene(cell_um);
  Solver<2> solver(sc);
  for (int s = 0; s < steps; ++s) solver.step();
  const auto t0 = std::chrono::steady_clock::now();
  for (int s = 0; s < timed; ++s) solver.step();
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();

  const Grid<2>& g = sc.grid;
  Census c;
  c.cell_um = cell_um;
  c.particles = static_cast<long>(sc.particles.size());
  c.nx = g.n[0];
  c.ny = g.n[1];
  c.strays = solver.stray_count();
  c.ns_per_update = 1e9 * wall / (static_cast<double>(c.particles) * timed);
  // what the scatter sums per node-field: mass, momentum, force, mass-centre offset, volume
  // gradient, and with the binder layer its five sums (contact/layer_data.hpp)
  const bool layer = sc.layer_data.on();
  c.bytes_per_node_field = 8.0 * (1 + 4 * 2 + (layer ? 2 + 4 + 1 + 2 + 1 : 0));
  const auto has_mass = [&](long i, long j) {
    int k = 0;
    for (int f = 0; f < g.deformable; ++f) k += g.mass[static_cast<std::size_t>(g.at(f, i + j * g.stride[1]))] > 0.0;
    return k;
  };
  StripBins bins;
  bins.setup(g.n[0] - 1);
  c.strip_width = bins.width;
  long cuts = 0, sum = 0;
  for (long s = 1; s < bins.strips; ++s) {
    const long b = s * bins.width;
    for (long i = b - 1; i <= b + 1; ++i)
      for (long j = 0; j < g.n[1]; ++j) sum += has_mass(i, j);
    ++cuts;
  }
  c.slab_node_fields = cuts ? static_cast<double>(sum) / static_cast<double>(cuts) : 0.0;
  // rows inside the specimen (between the die's floor and the punch): mass-holding node-fields
  // per node along the row, on three rows
  long rows = 0;
  sum = 0;
  for (long j = g.n[1] / 10; j < g.n[1] * 8 / 10; j += 3) {
    long row = 0;
    for (long r = j - 1; r <= j + 1; ++r)
      for (long i = 0; i < g.n[0]; ++i) row += has_mass(i, r);
    sum += row;
    ++rows;
  }
  c.row_node_fields = static_cast<double>(sum) / static_cast<double>(rows) / static_cast<double>(g.n[0]);
  return c;
}

// The decomposed USL step as built (docs/architecture.md, "One run over many ranks"): `steps`
// steps of the specimen after `warmup`, one process (rank 0 alone, the others waiting) against
// the run split over every rank, wall seconds of each (the slowest rank's).
void decomposed_step(double cell_um, int warmup, int steps, int rank, int size) {
  double t_one = 0;
  long np = 0;
  if (rank == 0) {
    Scene<2> sc = specimen_scene(cell_um);
    Solver<2> one(sc);
    np = static_cast<long>(sc.particles.size());
    for (int k = 0; k < warmup; ++k) one.step();
    one.stage_clock().clear();
    const auto t0 = std::chrono::steady_clock::now();
    for (int k = 0; k < steps; ++k) one.step();
    t_one = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    std::string line = "    stages, one process (wall s):";
    for (std::size_t k = 0; k < kStageNames.size(); ++k)
      line += fmt::format(" {} {:.3f}", kStageNames[k], one.stage_clock().seconds(static_cast<Stage>(k)));
    std::printf("%s\n", line.c_str());
  }
  MPI_Barrier(MPI_COMM_WORLD);
  Scene<2> whole = specimen_scene(cell_um);
  Solver<2> ref(whole);
  const std::vector<long>& sb = ref.strips().begin;
  const StripPartition part = partition_strips(sb, size);
  const long first = part.first[static_cast<std::size_t>(rank)], end = part.first[static_cast<std::size_t>(rank) + 1];
  Scene<2> mine = specimen_scene(cell_um);
  keep_particle_range(mine, static_cast<std::size_t>(sb[static_cast<std::size_t>(first)]),
                      static_cast<std::size_t>(sb[static_cast<std::size_t>(end)]));
  Solver<2> local(mine);
  StripExchange<2> ex(MPI_COMM_WORLD, mine.grid, &mine.layer_data.sums, ref.strips().width, ref.strips().strips, first,
                      end, mine.settings.kernel != Kernel::linear);
  local.set_scatter_exchange(&ex, ref.mass_threshold());
  for (int k = 0; k < warmup; ++k) local.step();
  local.stage_clock().clear();
  MPI_Barrier(MPI_COMM_WORLD);
  const auto t0 = std::chrono::steady_clock::now();
  for (int k = 0; k < steps; ++k) local.step();
  double t = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  MPI_Allreduce(MPI_IN_PLACE, &t, 1, MPI_DOUBLE, MPI_MAX, MPI_COMM_WORLD);
  long doubles = static_cast<long>(ex.message_doubles()), max_doubles = 0;
  MPI_Allreduce(&doubles, &max_doubles, 1, MPI_LONG, MPI_MAX, MPI_COMM_WORLD);
  long mine_n = static_cast<long>(mine.particles.size()), max_n = 0;
  MPI_Allreduce(&mine_n, &max_n, 1, MPI_LONG, MPI_MAX, MPI_COMM_WORLD);
  if (rank == 0) {
    std::string line = "    stages, rank 0 of the split run (wall s):";
    for (std::size_t k = 0; k < kStageNames.size(); ++k)
      line += fmt::format(" {} {:.3f}", kStageNames[k], local.stage_clock().seconds(static_cast<Stage>(k)));
    std::printf("%s\n", line.c_str());
  }
  if (rank == 0)
    std::printf(
        "  %5.1f um, %ld particles, steps %d-%d: one process %.3f s (%.3g particle-updates/s); %d ranks %.3f s "
        "(%.3g /s); speed-up %.2f, efficiency %.0f %% (the largest rank holds %ld particles, %.0f %% of an even "
        "share); the largest message sent %.1f kB (the mass-holding entries and their indices)\n",
        cell_um, np, warmup, warmup + steps, t_one, np * steps / t_one, size, t, np * steps / t, t_one / t,
        100 * t_one / (size * t), max_n, 100.0 * max_n * size / np, 8e-3 * static_cast<double>(max_doubles));
}

// One-way time of a both-ways exchange of `bytes` between ranks 0 and 1 (`pair`), best of 3 rounds.
double exchange_seconds(long bytes, int rank, MPI_Comm pair) {
  std::vector<char> out(static_cast<std::size_t>(std::max(1L, bytes)), 1), in(out.size());
  const int peer = 1 - rank;
  const int reps = bytes < 65536 ? 2000 : bytes < 4194304 ? 100 : 10;
  double best = 1e30;
  for (int round = 0; round < 3; ++round) {
    MPI_Barrier(pair);
    const double t0 = MPI_Wtime();
    for (int r = 0; r < reps; ++r)
      MPI_Sendrecv(out.data(), static_cast<int>(bytes), MPI_BYTE, peer, 7, in.data(), static_cast<int>(bytes), MPI_BYTE,
                   peer, 7, pair, MPI_STATUS_IGNORE);
    double t = (MPI_Wtime() - t0) / reps;
    MPI_Allreduce(MPI_IN_PLACE, &t, 1, MPI_DOUBLE, MPI_MAX, pair);
    best = std::min(best, t);
  }
  return best;
}

// The protocol assumed (docs/performance/engine.md): per step and per neighbour, the two
// scatter passes (the fused G2P/stress/P2G pass, the binder-layer springs' transfer) each send
// the even phase's partial sums of the shared lines one way and the final sums back (4 messages
// of the halo's bytes), the strays' pipeline two short messages, and the whole run one
// allreduce of the time step (2 log2 P latencies).
struct Model {
  double alpha, beta;  // s, bytes/s
  double step_seconds(double particles_per_rank, double ns_per_update, double halo_bytes, int neighbours,
                      int ranks) const {
    const double comp = particles_per_rank * ns_per_update * 1e-9;
    const double comm = neighbours * (4 * (alpha + halo_bytes / beta) + 2 * alpha) + 2 * alpha * std::log2(ranks);
    return comp + comm;
  }
  double efficiency(double particles_per_rank, double ns_per_update, double halo_bytes, int neighbours,
                    int ranks) const {
    const double comp = particles_per_rank * ns_per_update * 1e-9;
    return comp / step_seconds(particles_per_rank, ns_per_update, halo_bytes, neighbours, ranks);
  }
};

void print_predictions(const Census& ref, const Model& m, const char* network) {
  // name, particles, nodes along x and y (nodes of the specimen's box), dimension, node-fields per
  // shared node line per node from the reference census, time per particle-update
  struct Config {
    const char* name;
    double particles, nx, ny, nz;
    int dim;
  };
  const double scale = ref.cell_um / 0.6;
  const std::vector<Config> configs = {
      {"2-D full (2.5 um)", ref.particles * std::pow(ref.cell_um / 2.5, 2), ref.nx * ref.cell_um / 2.5,
       ref.ny * ref.cell_um / 2.5, 1, 2},
      {"2-D 0.6 um", ref.particles * scale * scale, ref.nx * scale, ref.ny * scale, 1, 2},
      {"3-D 1.0 x 1.2 x 1.0 mm at 2.5 um", 8.0 * 400 * 480 * 400 * 0.92, 400, 480, 400, 3},
  };
  // node-fields with mass per node of a shared line (three lines per cut)
  const double per_node = ref.row_node_fields / 3.0;
  std::printf("\nPredicted parallel efficiency (%s: alpha %.2f us, beta %.1f GB/s; no overlap of exchange and work)\n",
              network, m.alpha * 1e6, m.beta * 1e-9);
  std::printf("%-34s %8s %14s %16s %14s %12s\n", "specimen", "ranks", "particles/rank", "halo bytes/msg",
              "comm/step us", "efficiency");
  for (const auto& c : configs) {
    const double bytes_node_field = c.dim == 2 ? ref.bytes_per_node_field : 8.0 * (1 + 4 * 3 + 3 + 9 + 1 + 3 + 1);
    // 3-D: 27-node stencils against 9, so about 3x the work per particle-update (an estimate)
    const double ns = ref.ns_per_update * (c.dim == 3 ? 3.0 : 1.0);
    for (int P : {16, 64, 256, 1024}) {
      // tiles: P split as evenly as the box allows over its axes
      double px = 1, py = 1, pz = 1;
      if (c.dim == 2) {
        px = std::round(std::sqrt(P * c.nx / c.ny));
        px = std::max(1.0, std::min(static_cast<double>(P), px));
        while (P % static_cast<int>(px) != 0) px -= 1;
        py = P / px;
      } else {
        pz = std::round(std::cbrt(P));
        while (P % static_cast<int>(pz) != 0) pz -= 1;
        const int rest = P / static_cast<int>(pz);
        px = std::round(std::sqrt(rest));
        while (rest % static_cast<int>(px) != 0) px -= 1;
        py = rest / px;
      }
      // the largest face of a tile: nodes along it x three lines x node-fields per node x bytes
      const double face_x = c.dim == 2 ? c.ny / py : (c.ny / py) * (c.nz / pz);
      const double face_y = c.dim == 2 ? c.nx / px : (c.nx / px) * (c.nz / pz);
      const double face = std::max(px > 1 ? face_x : 0.0, py > 1 ? face_y : 0.0);
      const double bytes = face * 3 * per_node * bytes_node_field;
      const int neighbours = (px > 1 ? 2 : 0) + (py > 1 ? 2 : 0) + (pz > 1 ? 2 : 0);
      const double n = c.particles / P;
      const double t = m.step_seconds(n, ns, bytes, neighbours, P) - n * ns * 1e-9;
      std::printf("%-34s %8d %14.3g %16.3g %14.1f %11.0f%%\n", c.name, P, n, bytes, t * 1e6,
                  100 * m.efficiency(n, ns, bytes, neighbours, P));
    }
  }
}

}  // namespace

int main(int argc, char** argv) {
  MPI_Init(&argc, &argv);
  int rank = 0, size = 1;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  MPI_Comm_size(MPI_COMM_WORLD, &size);
  int code = 0;
  try {
    std::vector<double> cells = {20, 10, 5};
    int steps = 50, timed = 100;
    double alpha_us = 1.5, beta_gb = 12.0;
    for (int i = 1; i < argc; ++i) {
      const std::string a = argv[i];
      if (i + 1 >= argc) throw std::runtime_error("option " + a + " needs a value");
      const std::string v = argv[++i];
      if (a == "--cells") {
        cells.clear();
        std::stringstream ss(v);
        for (std::string item; std::getline(ss, item, ',');) cells.push_back(std::stod(item));
      } else if (a == "--steps")
        steps = std::stoi(v);
      else if (a == "--timed")
        timed = std::stoi(v);
      else if (a == "--alpha")
        alpha_us = std::stod(v);
      else if (a == "--beta")
        beta_gb = std::stod(v);
      else
        throw std::runtime_error("unknown option " + a);
    }
    omp_set_num_threads(1);
    std::vector<Census> cs;
    if (rank == 0) {
      std::printf("Halo census of the paper specimen (293 K, phi = 0.08, seed 1), after %d steps; one thread\n", steps);
      std::printf("%8s %10s %6s %6s %6s %7s %18s %22s %10s %12s\n", "cell um", "particles", "nx", "ny", "strip",
                  "strays", "x-cut node-fields", "row node-fields/node", "bytes/nf", "ns/update");
      for (double h : cells) {
        cs.push_back(census(h, steps, timed));
        const Census& c = cs.back();
        std::printf("%8.1f %10ld %6ld %6ld %6ld %7ld %18.0f %22.2f %10.0f %12.1f\n", c.cell_um, c.particles, c.nx, c.ny,
                    c.strip_width, c.strays, c.slab_node_fields, c.row_node_fields, c.bytes_per_node_field,
                    c.ns_per_update);
        std::fflush(stdout);
      }
    }
    double alpha = 0.5e-6, beta = 5e9;  // replaced by the measured values with 2 ranks
    // ranks 0 and 1 time the exchanges between them; the others wait
    MPI_Comm pair = MPI_COMM_NULL;
    if (size >= 2) MPI_Comm_split(MPI_COMM_WORLD, rank < 2 ? 0 : MPI_UNDEFINED, rank, &pair);
    if (size >= 2 && rank < 2) {
      std::vector<long> sizes;
      for (long b = 8; b <= 16L << 20; b *= 4) sizes.push_back(b);
      std::vector<double> t;
      for (long b : sizes) t.push_back(exchange_seconds(b, rank, pair));
      Eigen::MatrixXd A(static_cast<Eigen::Index>(sizes.size()), 2);
      Eigen::VectorXd y(A.rows());
      for (Eigen::Index k = 0; k < A.rows(); ++k) {
        A(k, 0) = 1.0;
        A(k, 1) = static_cast<double>(sizes[static_cast<std::size_t>(k)]);
        y(k) = t[static_cast<std::size_t>(k)];
      }
      // weighted by 1/t: the fit must hold for small messages (latency) as for large (bandwidth)
      const Eigen::VectorXd w = y.cwiseInverse();
      const Eigen::Vector2d p = (w.asDiagonal() * A).colPivHouseholderQr().solve(w.asDiagonal() * y);
      alpha = p(0);
      beta = 1.0 / p(1);
      if (rank == 0) {
        std::printf("\nExchange between 2 ranks (MPI_Sendrecv both ways, one-way time, best of 3)\n");
        for (std::size_t k = 0; k < sizes.size(); ++k)
          std::printf("  %10ld B  %10.2f us  %8.2f GB/s   fit %10.2f us\n", sizes[k], t[k] * 1e6,
                      static_cast<double>(sizes[k]) / t[k] * 1e-9,
                      (alpha + static_cast<double>(sizes[k]) / beta) * 1e6);
        std::printf("  fit: alpha %.2f us, beta %.2f GB/s\n", alpha * 1e6, beta * 1e-9);
      }
    }
    MPI_Bcast(&alpha, 1, MPI_DOUBLE, 0, MPI_COMM_WORLD);
    MPI_Bcast(&beta, 1, MPI_DOUBLE, 0, MPI_COMM_WORLD);
    // each census's own halo, timed: x-slab cut (3 columns) of the specimen
    long n_cs = static_cast<long>(cs.size());
    MPI_Bcast(&n_cs, 1, MPI_LONG, 0, MPI_COMM_WORLD);
    std::vector<double> halo(static_cast<std::size_t>(n_cs));
    for (long k = 0; k < n_cs; ++k)
      if (rank == 0)
        halo[static_cast<std::size_t>(k)] =
            cs[static_cast<std::size_t>(k)].slab_node_fields * cs[static_cast<std::size_t>(k)].bytes_per_node_field;
    MPI_Bcast(halo.data(), static_cast<int>(n_cs), MPI_DOUBLE, 0, MPI_COMM_WORLD);
    if (size >= 2 && n_cs > 0) {
      if (rank == 0)
        std::printf("\nThe specimen's own halo (one x-cut between two slabs), exchanged between 2 ranks\n");
      for (long k = 0; k < n_cs; ++k) {
        const double t =
            rank < 2 ? exchange_seconds(static_cast<long>(halo[static_cast<std::size_t>(k)]), rank, pair) : 0;
        if (rank == 0) {
          const Census& c = cs[static_cast<std::size_t>(k)];
          const Model here{alpha, beta};
          const double half = static_cast<double>(c.particles) / 2;
          const double comm = 4 * t + 2 * alpha;
          const double comp = half * c.ns_per_update * 1e-9;
          std::printf(
              "  %5.1f um: %8.0f B per message, %7.2f us measured; step of one of 2 slabs: work %8.1f us, "
              "exchanges %6.1f us -> %5.1f %% (model %5.1f %%)\n",
              c.cell_um, halo[static_cast<std::size_t>(k)], t * 1e6, comp * 1e6, comm * 1e6, 100 * comp / (comp + comm),
              100 * here.efficiency(half, c.ns_per_update, halo[static_cast<std::size_t>(k)], 1, 2));
        }
      }
    }
    if (size >= 2) {
      if (rank == 0)
        std::printf("\nThe decomposed USL step as built (no strays, sums per rank), one thread per rank\n");
      for (double h : cells) decomposed_step(h, 200, h < 10 ? 200 : 1000, rank, size);
    }
    if (rank == 0 && !cs.empty()) {
      // the finest census measured stands for the finer resolutions (its node-fields per node)
      const Census& ref = *std::min_element(cs.begin(), cs.end(),
                                            [](const Census& a, const Census& b) { return a.cell_um < b.cell_um; });
      if (size >= 2) print_predictions(ref, Model{alpha, beta}, "this machine, shared memory");
      print_predictions(ref, Model{alpha_us * 1e-6, beta_gb * 1e9}, "a cluster network");
    }
    if (pair != MPI_COMM_NULL) MPI_Comm_free(&pair);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "bench_halo: %s\n", e.what());
    code = 1;
  }
  MPI_Finalize();
  return code;
}
