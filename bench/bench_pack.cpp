// Packing and rasterisation throughput: the paper's 1.0 x 1.2 mm box at porosity 0.053 (issue 5
// asks <= 10 s on one core) and 0.0798, and rasterising at the default resolution.
#include <benchmark/benchmark.h>

#include "io/deck.hpp"
#include "microstructure/packing.hpp"
#include "microstructure/rasterise.hpp"

namespace {

pbx::PackingSpec spec(const char* name) {
  pbx::Deck d = pbx::Deck::from_file(std::string(PBXMPM_SOURCE_DIR "/examples/packing/") + name);
  return pbx::read_packing_spec(d.root().table("packing"));
}

void BM_pack(benchmark::State& state, const char* deck) {
  const pbx::PackingSpec s = spec(deck);
  for (auto _ : state) {
    pbx::Packing p = pbx::generate_packing(s);
    benchmark::DoNotOptimize(p.stats.porosity);
    state.counters["grains"] = static_cast<double>(p.grains.size());
  }
}
BENCHMARK_CAPTURE(BM_pack, porosity_0053, "porosity_0.053.toml")->Unit(benchmark::kSecond)->Iterations(1);
BENCHMARK_CAPTURE(BM_pack, porosity_00798, "porosity_0.0798.toml")->Unit(benchmark::kSecond)->Iterations(1);

void BM_rasterise(benchmark::State& state) {
  const pbx::Packing p = pbx::generate_packing(spec("porosity_0.0798.toml"));
  for (auto _ : state) {
    auto seeds = pbx::rasterise(p, pbx::kDefaultCellSize, pbx::kDefaultParticlesPerAxis, {0, 0});
    state.counters["particles"] = static_cast<double>(seeds.size());
    benchmark::DoNotOptimize(seeds.data());
  }
}
BENCHMARK(BM_rasterise)->Unit(benchmark::kSecond)->Iterations(1);

}  // namespace

BENCHMARK_MAIN();
