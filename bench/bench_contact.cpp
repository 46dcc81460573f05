// Cost of multi-field contact: the wall time of a step with 6 fields (binder, four grain colours,
// the die's rigid bodies) against the same particles on a single velocity field (every body
// welded). Specimen: a 0.5 x 0.6 mm die at 5 um cells, 6 x 7 grains (radius 32 um, colours by a
// 2 x 2 checkerboard so touching neighbours never share a field) in a binder matrix, linear
// elastic, Coulomb mu = 0.3 between every pair of fields. Usage: bench_contact [steps=100] [threads...=1 2]
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

using namespace pbx;

namespace {

std::string specimen(bool colours) {
  std::string text = R"(
[run]
end_strain = 0.01
[grid]
cell_size = "5 um"
[solver]
mass_scaling = 100
[die]
width = "0.5 mm"
height = "0.6 mm"
punch_velocity = "0.3 m/s"
wall_friction = 0.3
[materials.tatb]
model = "linear_elastic"
density = "1.934 g/cm3"
bulk_modulus = "10.59 GPa"
shear_modulus = "11.5 GPa"
[materials.binder]
model = "linear_elastic"
density = "2.02 g/cm3"
youngs_modulus = "1 GPa"
poisson_ratio = 0.4
)";
  for (int i = 0; i < 6; ++i)
    for (int j = 0; j < 7; ++j)
      text += fmt::format(R"(
[[geometry]]
shape = "disk"
center = ["{} um", "{} um"]
radius = "32 um"
material = "tatb"
field = "{}"
)",
                          50 + 80 * i, 60 + 80 * j, colours ? fmt::format("tatb_{}", i % 2 + 2 * (j % 2)) : "all");
  text += fmt::format(R"(
[[geometry]]
min = ["0 mm", "0 mm"]
max = ["0.5 mm", "0.6 mm"]
material = "binder"
field = "{}"
)",
                      colours ? "binder" : "all");
  if (colours) text += "[contact]\ndefault = \"coulomb\"\nfriction = 0.3\n";
  return text;
}

// Wall seconds per step over `steps` steps after 5 warm-up steps.
double seconds_per_step(bool colours, int steps, std::size_t& particles, int& fields) {
  Deck deck = Deck::from_string(specimen(colours), "bench_contact");
  Scene<2> sc = build_scene<2>(deck);
  Solver<2> solver(sc);
  particles = sc.particles.size();
  fields = sc.deformable_fields;
  for (int s = 0; s < 5; ++s) solver.step();
  const auto t0 = std::chrono::steady_clock::now();
  for (int s = 0; s < steps; ++s) solver.step();
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count() / steps;
}

}  // namespace

int main(int argc, char** argv) {
  const int steps = argc > 1 ? std::atoi(argv[1]) : 100;
  std::vector<int> threads;
  for (int i = 2; i < argc; ++i) threads.push_back(std::atoi(argv[i]));
  if (threads.empty()) threads = {1, 2};
  for (int t : threads) {
    omp_set_num_threads(t);
    std::size_t n1 = 0, n6 = 0;
    int f1 = 0, f6 = 0;
    const double single = seconds_per_step(false, steps, n1, f1);
    const double multi = seconds_per_step(true, steps, n6, f6);
    std::printf(
        "threads %d  particles %zu  steps %d  single field (%d deformable): %.3f ms/step  "
        "%d deformable fields + die: %.3f ms/step  ratio %.2f\n",
        t, n6, steps, f1, 1e3 * single, f6, 1e3 * multi, multi / single);
  }
  return 0;
}
