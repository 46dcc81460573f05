// Exact circle-union area clipped to the box, against closed-form areas.
#include <cmath>
#include <numbers>

#include <gtest/gtest.h>

#include "microstructure/union_area.hpp"

using namespace pbx;
constexpr double pi = std::numbers::pi;

TEST(UnionArea, DiskInsideHalfDiskAndQuarterDisk) {
  const Eigen::Vector2d box(10, 8);
  EXPECT_NEAR(union_area_in_box({{{5, 4}, 2}}, box), pi * 4, 1e-12);
  EXPECT_NEAR(union_area_in_box({{{0, 4}, 2}}, box), pi * 2, 1e-12);  // cut by the left edge
  EXPECT_NEAR(union_area_in_box({{{10, 8}, 2}}, box), pi, 1e-12);     // top-right corner
  EXPECT_NEAR(union_area_in_box({{{5, 4}, 100}}, box), 80, 1e-9);     // covers the box
}

TEST(UnionArea, TwoOverlappingDisksLoseTheLens) {
  // Lens of two radius-R disks at distance d: 2 R^2 acos(d/2R) - (d/2) sqrt(4R^2 - d^2).
  const double R = 1.5, d = 2.0;
  const double lens = 2 * R * R * std::acos(d / (2 * R)) - 0.5 * d * std::sqrt(4 * R * R - d * d);
  const double got = union_area_in_box({{{4, 4}, R}, {{4 + d, 4}, R}}, {10, 8});
  EXPECT_NEAR(got, 2 * pi * R * R - lens, 1e-12);
  // A disk inside another adds nothing; an identical copy adds nothing.
  EXPECT_NEAR(union_area_in_box({{{4, 4}, 2}, {{4.5, 4}, 1}, {{4, 4}, 2}}, {10, 8}), 4 * pi, 1e-12);
}

TEST(UnionArea, LensCutByAnEdge) {
  // Two equal disks centred on the bottom edge: exactly half of their union lies in the box.
  const double R = 1.5, d = 2.0;
  const double lens = 2 * R * R * std::acos(d / (2 * R)) - 0.5 * d * std::sqrt(4 * R * R - d * d);
  EXPECT_NEAR(union_area_in_box({{{4, 0}, R}, {{4 + d, 0}, R}}, {10, 8}), 0.5 * (2 * pi * R * R - lens), 1e-12);
}
