// Per-particle stress-update cost of each material model (one core, plane strain, one batch of
// 16384 particles per update call). Counter ns_per_particle = wall time / (particles x steps).
// Targets (issue 3): <= 50 ns for j2_mie_gruneisen, <= 80 ns for 8-term viscoelastic_tait.
#include <cstdint>
#include <random>
#include <string>
#include <vector>

#include <benchmark/benchmark.h>

#include "io/deck.hpp"
#include "materials/material.hpp"

using namespace pbx;

namespace {

const char* kDeck = R"(
[materials.linear_elastic]
model = "linear_elastic"
density = 1934.0
bulk_modulus = 10.59e9
shear_modulus = 11.5e9

[materials.tatb]
model = "j2_mie_gruneisen"
density = "1.934 g/cm3"
shear_modulus = "11.5 GPa"
yield_stress = "0.80 GPa"
sound_speed = "2340 m/s"
hugoniot_s1 = 2.32
gruneisen_gamma0 = 1.60

[materials.f2314]
model = "viscoelastic_tait"
density = "2.02 g/cm3"
thermal_expansion = "4.5e-4 1/K"
long_term_shear_modulus = "10 MPa"
prony_shear_moduli = ["12.5 MPa", "12.5 MPa", "12.5 MPa", "12.5 MPa", "12.5 MPa", "12.5 MPa", "12.5 MPa", "12.5 MPa"]
prony_shear_times = [1e-7, 1e-6, 1e-5, 1e-4, 1e-3, 1e-2, 1e-1, 1.0]
shift = "arrhenius"
activation_energy = "100 kJ/mol"
tait_c = 0.08936
tait_k0 = "0.27 GPa"
tait_b1 = "4e-3 1/K"
)";

void BM_MaterialUpdate(benchmark::State& state, const std::string& name) {
  const Deck deck = Deck::from_string(kDeck, "bench.toml");
  MaterialContext ctx;
  ctx.temperature = 333.0;
  ctx.name = name;
  const auto m = make_material<2>(deck.root().table("materials").table(name), ctx);
  const std::size_t n = 16384;
  std::vector<std::uint32_t> index(n);
  std::vector<Mat<2>> L(n), F(n);
  std::vector<double> mass(n), vol(n), vol0(n, 1e-12);
  std::vector<Sym3> stress(n);
  std::vector<double> hist(n * static_cast<std::size_t>(m->history_size()));
  std::mt19937 rng(1);
  std::uniform_real_distribution<double> u(-300.0, 300.0);
  for (std::size_t k = 0; k < n; ++k) {
    index[k] = static_cast<std::uint32_t>(k);
    L[k] << u(rng), u(rng), u(rng), u(rng);
    F[k] = Mat<2>::Identity() * 0.997;
    vol[k] = vol0[k] * F[k].determinant();
    mass[k] = m->density() * vol0[k];
    if (m->history_size() > 0) m->init_history(&hist[k * m->history_size()]);
  }
  MaterialBatch<2> b;
  b.index = index;
  b.L = L.data();
  b.F = F.data();
  b.mass = mass.data();
  b.volume = vol.data();
  b.volume0 = vol0.data();
  b.stress = stress.data();
  b.history = hist.data();
  b.dt = 2e-9;
  for (auto _ : state) {
    auto r = m->update(b);
    benchmark::DoNotOptimize(r);
  }
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations() * n));
  state.counters["ns_per_particle"] = benchmark::Counter(static_cast<double>(state.iterations() * n) * 1e-9,
                                                         benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
}

}  // namespace

BENCHMARK_CAPTURE(BM_MaterialUpdate, linear_elastic, std::string("linear_elastic"))->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(BM_MaterialUpdate, j2_mie_gruneisen_tatb, std::string("tatb"))->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(BM_MaterialUpdate, viscoelastic8_tait_f2314, std::string("f2314"))->Unit(benchmark::kMicrosecond);
BENCHMARK_MAIN();
