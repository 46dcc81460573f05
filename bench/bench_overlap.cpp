// Cost of the interpenetration measure (contact/field_overlap.hpp), which the runner evaluates once
// per history row: the paper box (1.0 x 1.2 mm in a grid with a 4-cell margin) filled with the
// rasterised particles of a given cell size (2 x 2 per cell, fields in a 4-colour checkerboard of
// 100 um blocks), each particle nudged at random by up to 30 % of its spacing so that neighbours
// overlap. Prints the time per call and the raster size. Usage: bench_overlap [cell_um=2.5] [calls=20]
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <random>

#include "contact/field_overlap.hpp"

using namespace pbx;

int main(int argc, char** argv) {
  const double h = (argc > 1 ? std::atof(argv[1]) : 2.5) * 1e-6;
  const int calls = argc > 2 ? std::atoi(argv[2]) : 20;
  Grid<2> g;
  g.h = h;
  g.origin = Vec<2>(-4 * h, -4 * h);
  g.n = {static_cast<long>(1.0e-3 / h) + 9, static_cast<long>(1.2e-3 / h) + 9};
  g.allocate(0);
  Particles<2> P;
  const double s = h / 2;
  std::mt19937_64 rng(1);
  std::uniform_real_distribution<double> nudge(-0.3 * s, 0.3 * s);
  for (long j = 0; j < static_cast<long>(1.2e-3 / s); ++j)
    for (long i = 0; i < static_cast<long>(1.0e-3 / s); ++i) {
      const Vec<2> x((i + 0.5) * s + nudge(rng), (j + 0.5) * s + nudge(rng));
      const int field = static_cast<int>(x[0] / 100e-6) % 2 + 2 * (static_cast<int>(x[1] / 100e-6) % 2);
      P.add(x, s * s, 1e-9, 0, field);
    }
  FieldOverlap o(g, FieldOverlap::default_pixel(P));
  double area = 0;
  const auto t0 = std::chrono::steady_clock::now();
  for (int c = 0; c < calls; ++c) area = o.area(P);
  const double dt = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count() / calls;
  std::printf("cell %.3g um  particles %zu  pixel %.3g um  raster %.1f MB  %.2f ms per call  overlap %.4g um2\n",
              h * 1e6, P.size(), o.pixel() * 1e6,
              4.0 * (g.h * (g.n[0] - 1) / o.pixel()) * (g.h * (g.n[1] - 1) / o.pixel()) / 1e6, dt * 1e3, area * 1e12);
  return 0;
}
