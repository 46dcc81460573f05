// Whole-step throughput on the real workload: the paper specimen of the quick study
// (examples/paper/base.toml at 20 um cells, 293 K, porosity 0.08, seed 1: about 11,000 particles
// on ten grain fields and a binder field, J2 + Mie-Grueneisen TATB, Prony + Tait binder,
// binder_layer and Coulomb contact between the fields, a rigid die and a moving punch). The same
// timed loop and output as bench_engine (bench/step_timing.hpp), so the two compare line by line;
// bench/specimen-vs-block runs both interleaved, best of 3.
// The specimen is stepped from rest: `warmup` steps untimed (the punch ramp, 0.05 % strain, takes
// about 2,000), then `steps` timed, during which the punch compresses it.
// Usage: bench_specimen [steps=2000] [threads...=1 2] [--warmup N] [--set KEY=VALUE ...]
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <omp.h>

#include "io/deck.hpp"
#include "setup/build_scene.hpp"
#include "io/deck_override.hpp"
#include "solver/solver.hpp"
#include "step_timing.hpp"

using namespace pbx;

int main(int argc, char** argv) try {
  int steps = 2000, warmup = 2500;
  std::vector<int> threads;
  std::vector<DeckOverride> set = {{"grid.cell_size", "\"20 um\""},
                                   {"packing.porosity", "0.08"},
                                   {"run.temperature", "\"293 K\""},
                                   {"specimen.seed", "1"}};
  bool steps_given = false;
  for (int i = 1; i < argc; ++i) {
    if (!std::strcmp(argv[i], "--set") && i + 1 < argc)
      set.push_back(parse_override_option(argv[++i]));
    else if (!std::strcmp(argv[i], "--warmup") && i + 1 < argc)
      warmup = std::atoi(argv[++i]);
    else if (!steps_given && std::isdigit(static_cast<unsigned char>(argv[i][0]))) {
      steps = std::atoi(argv[i]);
      steps_given = true;
    } else if (std::isdigit(static_cast<unsigned char>(argv[i][0])))
      threads.push_back(std::atoi(argv[i]));
    else {
      std::fprintf(stderr, "bench_specimen: unknown argument '%s'\n", argv[i]);
      return 2;
    }
  }
  if (threads.empty()) threads = {1, 2};
  const std::string dir = PBXMPM_SOURCE_DIR "/examples/paper";
  const std::string file = dir + "/base.toml";
  std::ifstream in(file);
  if (!in) throw std::runtime_error("cannot read " + file);
  std::stringstream ss;
  ss << in.rdbuf();
  const std::string text = deck_with_overrides(ss.str(), file, set);
  for (int t : threads) {
    omp_set_num_threads(t);
    Deck deck = Deck::from_string(text, file, dir);
    Scene<2> sc = build_scene<2>(deck, SceneNotes::quiet);
    Solver<2> solver(sc);
    const bench::StepTiming r = bench::time_steps(solver, steps, warmup);
    const double n = static_cast<double>(sc.particles.size());
    std::printf(
        "specimen  threads %d  particles %.0f  fields %d  steps %d  wall %.3f s  %.3g particle-updates/s  "
        "user %.3f s  cpu %.3f s  %.3g particle-updates/cpu-s  peak RSS %.1f MB  strain at end %.3f %%\n",
        t, n, sc.grid.fields, steps, r.wall, r.updates_per_s, r.user, r.cpu, n * steps / r.cpu, r.peak_rss_mb,
        100.0 * -sc.bodies[sc.die->punch].displacement_at(solver.time())[1] / sc.die->height);
    bench::print_stages(solver, steps);
    // the contact stage's work: nodes by the number of deformable fields with mass there
    std::vector<long> census(static_cast<std::size_t>(sc.grid.deformable) + 1, 0);
    for (long i = 0; i < sc.grid.nodes(); ++i) {
      int k = 0;
      for (int f = 0; f < sc.grid.deformable; ++f) k += sc.grid.mass[sc.grid.at(f, i)] > 0.0;
      ++census[static_cast<std::size_t>(k)];
    }
    long bonded = 0;
    for (const auto b : sc.layer_data.particles.bonded) bonded += b;
    std::string line = fmt::format("  bonded particles {} of {}; nodes {} by fields present:", bonded,
                                   sc.particles.size(), sc.grid.nodes());
    for (std::size_t k = 0; k < census.size(); ++k)
      if (census[k]) line += fmt::format("  {}: {}", k, census[k]);
    std::printf("%s\n", line.c_str());
  }
  return 0;
} catch (const std::exception& e) {
  std::fprintf(stderr, "bench_specimen: %s\n", e.what());
  return 1;
}
