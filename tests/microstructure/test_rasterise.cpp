// Packing -> particles: order, placement, and the particle set's mass ratio and porosity against
// the exact geometry at the default resolution.
#include <cmath>
#include <numbers>

#include <gtest/gtest.h>

#include "core/error.hpp"
#include "microstructure/rasterise.hpp"

using namespace pbx;

namespace {

// Hand-made packing: two coated grains in a 100 x 80 um box (walls), exact areas known.
Packing two_grains() {
  Packing p;
  p.box = {100e-6, 80e-6};
  p.periodic = false;
  p.tatb_density = 1934;
  p.binder_density = 2020;
  p.grains.push_back({{30e-6, 40e-6}, 40e-6, 2e-6, 0, 0});
  p.grains.push_back({{72e-6, 40e-6}, 40e-6, 2e-6, 1, 0});  // coats overlap by 2 um
  measure(p);
  return p;
}

}  // namespace

TEST(Rasterise, ParticlesAreCellSortedOnTheSubGrid) {
  const Packing p = two_grains();
  const Eigen::Vector2d origin(-7e-6, 3e-6);
  const double h = 4e-6;
  const auto s = rasterise(p, h, 2, origin);
  ASSERT_FALSE(s.empty());
  long prev = -1;
  for (const auto& q : s) {
    const Eigen::Vector2d local = (q.x - origin) / h;
    const long ci = static_cast<long>(std::floor(local.x())), cj = static_cast<long>(std::floor(local.y()));
    const long cell = cj * 25 + ci;  // 25 cells across 100 um
    EXPECT_GE(cell, prev);
    prev = cell;
    // Sub-cell centres: fractional positions 0.25 or 0.75 of the cell.
    for (int a = 0; a < 2; ++a) {
      const double f = local[a] - std::floor(local[a]);
      EXPECT_TRUE(std::abs(f - 0.25) < 1e-9 || std::abs(f - 0.75) < 1e-9) << f;
    }
    EXPECT_DOUBLE_EQ(q.volume, 4e-12);
    if (q.phase == 0) {
      EXPECT_GE(q.grain, 0);
      EXPECT_EQ(q.colour, p.grains[q.grain].colour);
      EXPECT_LT((q.x - origin - p.grains[q.grain].centre).norm(), 20e-6);
    } else {
      EXPECT_EQ(q.phase, 1);
      EXPECT_EQ(q.grain, -1);
      EXPECT_EQ(q.colour, -1);
    }
  }
}

TEST(Rasterise, MassRatioAndPorosityConvergeToTheGeometry) {
  const Packing p = two_grains();
  // Geometry: TATB 2 pi 20^2 um^2; binder = coat union minus TATB, with the lens of the coats.
  const double R = 22e-6, d = 42e-6;
  const double lens = 2 * R * R * std::acos(d / (2 * R)) - 0.5 * d * std::sqrt(4 * R * R - d * d);
  const double tatb = 2 * std::numbers::pi * 400e-12, binder = 2 * std::numbers::pi * R * R - lens - tatb;
  EXPECT_NEAR(p.stats.tatb_area_fraction * p.box.prod(), tatb, 1e-20);
  EXPECT_NEAR(p.stats.binder_area_fraction * p.box.prod(), binder, 1e-20);
  const auto r = raster_report(rasterise(p, 0.25e-6, 2, {0, 0}), p.box, 1934, 2020);
  EXPECT_NEAR(r.tatb_to_binder_mass / (tatb * 1934 / (binder * 2020)), 1.0, 0.005);
  EXPECT_NEAR(r.porosity / p.stats.porosity, 1.0, 0.005);
}

TEST(Rasterise, BadResolutionIsAnInputError) {
  const Packing p = two_grains();
  EXPECT_THROW(rasterise(p, 0.0, 2, {0, 0}), InputError);
  EXPECT_THROW(rasterise(p, 1e-6, 0, {0, 0}), InputError);
}
