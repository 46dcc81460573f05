// The field-overlap measure (contact/field_overlap.hpp): exact areas for hand-placed particle
// domains, zero for a tiled specimen, and, in the two-disk collision, small with the default
// contact detection and large when a displacement check below the touching distance lets the
// disks pass into each other (which also checks that the position check acts in a scene without
// rigid bodies: it once compared mass-centre offsets that were only scattered when a die existed).
#include <algorithm>
#include <cmath>
#include <string>

#include <gtest/gtest.h>

#include "../engine/scene_fixture.hpp"
#include "setup/build_scene.hpp"
#include "io/deck.hpp"
#include "two_disks_deck.hpp"
#include "contact/field_overlap.hpp"

using namespace pbx;

namespace {
Grid<2> small_grid() {
  Grid<2> g;
  g.h = 4e-6;
  g.n = {11, 11};  // 40 x 40 um
  g.allocate(2);
  return g;
}
constexpr double kSide = 2e-6;  // particle domain side (2 x 2 particles per 4 um cell)
}  // namespace

TEST(FieldOverlap, ExactAreaOfTwoOverlappingDomains) {
  Grid<2> g = small_grid();
  Particles<2> P;
  P.add(Vec<2>(10e-6, 10e-6), kSide * kSide, 1e-9, 0, 0);    // domain [9, 11] x [9, 11] um
  P.add(Vec<2>(11e-6, 10.5e-6), kSide * kSide, 1e-9, 0, 1);  // [10, 12] x [9.5, 11.5]: overlap 1 x 1.5 um
  FieldOverlap o(g, FieldOverlap::default_pixel(P));
  EXPECT_DOUBLE_EQ(o.pixel(), 0.5e-6);
  EXPECT_NEAR(o.area(P), 1.5e-12, 1e-24);
  P.field[1] = 0;  // the same field: a body overlapping itself is not interpenetration
  EXPECT_EQ(o.area(P), 0.0);
}

TEST(FieldOverlap, DomainsOutsideTheGridOrNotFiniteAreSkipped) {
  Grid<2> g = small_grid();
  Particles<2> P;
  P.add(Vec<2>(0.0, 10e-6), kSide * kSide, 1e-9, 0, 0);     // [-1, 1] um: half outside the left edge
  P.add(Vec<2>(0.5e-6, 10e-6), kSide * kSide, 1e-9, 0, 1);  // [-0.5, 1.5]: overlap in the grid [0, 1] x 2 um
  P.add(Vec<2>(1e300, -1e300), kSide * kSide, 1e-9, 0, 2);  // far away: no overflow
  P.add(Vec<2>(std::nan(""), 10e-6), kSide * kSide, 1e-9, 0, 3);
  FieldOverlap o(g, FieldOverlap::default_pixel(P));
  EXPECT_NEAR(o.area(P), 1e-6 * 2e-6, 1e-24);
}

TEST(FieldOverlap, PixelCoveredByThreeFieldsCountsOnce) {
  Grid<2> g = small_grid();
  Particles<2> P;
  for (int f = 0; f < 3; ++f) P.add(Vec<2>(20e-6, 20e-6), kSide * kSide, 1e-9, 0, f);
  FieldOverlap o(g, FieldOverlap::default_pixel(P));
  EXPECT_NEAR(o.area(P), kSide * kSide, 1e-24);
}

TEST(FieldOverlap, TiledDomainsOfAlternatingFieldsDoNotOverlap) {
  // A checkerboard of fields on the sub-cell centres of a rasterised specimen: every pair of
  // neighbours belongs to different fields and their domains share edges only.
  Grid<2> g = small_grid();
  Particles<2> P;
  for (int j = 0; j < 16; ++j)
    for (int i = 0; i < 16; ++i)
      P.add(Vec<2>((2 * i + 5) * 1e-6, (2 * j + 5) * 1e-6), kSide * kSide, 1e-9, 0, (i + j) % 2);
  FieldOverlap o(g, FieldOverlap::default_pixel(P));
  EXPECT_EQ(o.area(P), 0.0);
  // Shifting one column by a quarter of a domain overlaps it with its neighbours by 0.5 um x 32 um.
  for (std::size_t p = 0; p < P.size(); ++p)
    if (p % 16 == 3) P.x[p][0] += 0.5e-6;
  EXPECT_NEAR(o.area(P), 0.5e-6 * 32e-6, 1e-20);
}

TEST(FieldOverlap, DeformedTilingOfAPaperSpecimenStaysFreeOfOverlap) {
  // The paper specimen at 10 um cells: exactly 0 as rasterised; then every particle is moved and
  // deformed as by a homogeneous gradient (uniaxial 3 % compression, then a 20-degree rotation with
  // 2 % shear), under which the domains still tile: the measure must stay at the round-off level
  // (a few pixels), whereas squares of the current area would overlap along every horizontal field
  // boundary by s eps / 2.
  Deck deck = Deck::from_file(std::string(PBXMPM_SOURCE_DIR) + "/examples/paper/base.toml");
  Scene<2> sc = build_scene<2>(deck);
  Particles<2>& P = sc.particles;
  FieldOverlap o(sc.grid, FieldOverlap::default_pixel(P));
  EXPECT_EQ(o.area(P), 0.0);
  const double box = 1.0e-3 * 1.2e-3, pixel2 = o.pixel() * o.pixel();
  const Vec<2> centre(0.5e-3, 0.6e-3);
  Mat<2> uniaxial, turn;
  uniaxial << 1.0, 0.0, 0.0, 0.97;
  const double c = std::cos(0.349), sn = std::sin(0.349);
  turn << c, -sn, sn, c;
  Mat<2> shear;
  shear << 1.0, 0.02, 0.0, 1.0;
  for (const Mat<2>& F : {uniaxial, Mat<2>(turn * shear * uniaxial)}) {
    Particles<2> Q = P;
    for (std::size_t p = 0; p < Q.size(); ++p) {
      Q.x[p] = centre + F * (P.x[p] - centre);
      Q.F[p] = F;
      Q.volume[p] = F.determinant() * P.volume0[p];
    }
    const double a = o.area(Q);
    EXPECT_LT(a, 1e-6 * box) << a / pixel2 << " pixels";
  }
}

namespace {
// The two-disk collision (two_disks_deck.hpp, 5 um domains) with frictionless contact, stopped
// after the rebound; returns the largest overlap growth over the run.
double collision_overlap(const std::string& contact_extra) {
  Scene<2> sc = test::scene_from(test::two_disks_deck("frictionless", "4 us", 40, contact_extra));
  Runner<2> runner(sc, test::quiet());
  double first = -1, most = 0;
  runner.run([&](const Measurement& m) {
    EXPECT_EQ(m.field_overlap.size(), 1u);
    if (m.field_overlap.empty()) return;
    if (first < 0) first = m.field_overlap[0];
    most = std::max(most, m.field_overlap[0] - first);
  });
  EXPECT_EQ(first, 0.0);  // the rasterised disks start apart
  return most;
}
}  // namespace

TEST(FieldOverlap, DiskCollisionDefaultContactAgainstLateDetection) {
  const double disk = 3.14159265358979 * 60e-6 * 60e-6;
  const double normal = collision_overlap("");
  const double late = collision_overlap("position_check = 0.2");
  std::printf("overlap growth: default %.4g um2, position_check 0.2: %.4g um2 (disk %.4g um2)\n", normal * 1e12,
              late * 1e12, disk * 1e12);
  EXPECT_LT(normal, 1e-3 * disk);  // measured 0: the disks rebound about 1.5 cells apart
  EXPECT_GT(late, 1e-2 * disk);    // measured 481 um2 (4.3 %): they meet before the check lets contact act
}
