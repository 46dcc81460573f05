// Whole-step throughput of the engine: die compression of a linear-elastic block, uGIMP,
// 2 x 2 particles per cell, 200,000 particles (1.0 x 1.25 mm at 5 um cells). Prints
// particle-updates per second (particles x steps / wall s) at each thread count and the peak
// resident memory per particle. On a shared machine the wall figure depends on the load, so the
// CPU time of the process over the timed steps (user + system, all threads) is printed too:
// particle-updates per CPU-second is what one core would do with the machine to itself.
// Usage: bench_engine [steps=300] [threads...=1 2] [integrator=usl]
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <omp.h>

#include "io/deck.hpp"
#include "setup/build_scene.hpp"
#include "solver/solver.hpp"
#include "step_timing.hpp"

using namespace pbx;

int main(int argc, char** argv) {
  const int steps = argc > 1 ? std::atoi(argv[1]) : 300;
  std::vector<int> threads;
  std::string integrator = "usl";
  for (int i = 2; i < argc; ++i) {
    if (std::isdigit(static_cast<unsigned char>(argv[i][0])))
      threads.push_back(std::atoi(argv[i]));
    else
      integrator = argv[i];
  }
  if (threads.empty()) threads = {1, 2};
  const std::string deck_text = fmt::format(R"(
[run]
end_strain = 0.01
[grid]
cell_size = "5 um"
shape_function = "ugimp"
particles_per_cell = 2
[solver]
integrator = "{}"
mass_scaling = 100
[die]
width = "1.0 mm"
height = "1.25 mm"
punch_velocity = "0.3 m/s"
[materials.block]
model = "linear_elastic"
density = "1.934 g/cm3"
bulk_modulus = "10.59 GPa"
shear_modulus = "11.5 GPa"
[[geometry]]
min = ["0 mm", "0 mm"]
max = ["1.0 mm", "1.25 mm"]
material = "block"
)",
                                            integrator);
  for (int t : threads) {
    omp_set_num_threads(t);
    Deck deck = Deck::from_string(deck_text, "bench");
    Scene<2> sc = build_scene<2>(deck);
    Solver<2> solver(sc);
    const bench::StepTiming r = bench::time_steps(solver, steps);
    const double n = static_cast<double>(sc.particles.size());
    std::printf(
        "integrator %s  threads %d  particles %.0f  steps %d  wall %.3f s  %.3g particle-updates/s  "
        "user %.3f s  cpu %.3f s  %.3g particle-updates/cpu-s  peak RSS %.1f MB (%.0f bytes/particle)\n",
        integrator.c_str(), t, n, steps, r.wall, r.updates_per_s, r.user, r.cpu, n * steps / r.cpu, r.peak_rss_mb,
        r.peak_rss_mb * 1024.0 * 1024.0 / n);
    bench::print_stages(solver, steps);
  }
  return 0;
}
