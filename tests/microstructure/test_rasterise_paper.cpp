// The paper-size packing rasterised at the default resolution keeps its mass ratio and porosity
// within 0.5 % (the rasteriser's accuracy promise, docs/theory/microstructure.md).
#include <cstdio>

#include <gtest/gtest.h>

#include "io/deck.hpp"
#include "microstructure/rasterise.hpp"

using namespace pbx;

TEST(RasterisePaper, DefaultResolutionWithinHalfAPercent) {
  Deck d = Deck::from_file(PBXMPM_EXAMPLES_DIR "/packing/porosity_0.0798.toml");
  const Packing p = generate_packing(read_packing_spec(d.root().table("packing")));
  const auto seeds = rasterise(p, kDefaultCellSize, kDefaultParticlesPerAxis, {0, 0});
  const auto r = raster_report(seeds, p.box, p.tatb_density, p.binder_density);
  const double ratio = p.stats.tatb_mass_fraction / (1 - p.stats.tatb_mass_fraction);
  EXPECT_NEAR(r.tatb_to_binder_mass / ratio, 1.0, 0.005) << r.tatb_to_binder_mass << " vs " << ratio;
  RecordProperty("mass_ratio_particles", std::to_string(r.tatb_to_binder_mass));
  std::printf("particles %zu: TATB:binder mass %.5f (geometry %.5f), porosity %.5f (geometry %.5f)\n", r.particles,
              r.tatb_to_binder_mass, ratio, r.porosity, p.stats.porosity);
  EXPECT_NEAR(r.porosity / p.stats.porosity, 1.0, 0.005) << r.porosity << " vs " << p.stats.porosity;
  // Every grain is represented and carries its colour.
  std::vector<char> seen(p.grains.size(), 0);
  for (const auto& s : seeds)
    if (s.phase == 0) seen[s.grain] = 1;
  for (std::size_t g = 0; g < seen.size(); ++g) EXPECT_TRUE(seen[g]) << g;
}
