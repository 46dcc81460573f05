// Snapshots show the whole die: each time of snapshots.xmf holds the specimen's particles and the
// rigid bodies' particles (walls, punch) as a second grid, and the punch's particles in the last
// snapshot sit where the punch is at that time.
#include <filesystem>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <hdf5.h>
#include <unistd.h>

#include "block_deck.hpp"
#include "scene_fixture.hpp"

namespace fs = std::filesystem;
using namespace pbx;

namespace {
std::vector<double> read_doubles(const std::string& file, const char* name) {
  std::vector<double> v;
  hid_t f = H5Fopen(file.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  if (f < 0) return v;
  hid_t ds = H5Dopen2(f, name, H5P_DEFAULT);
  if (ds >= 0) {
    hid_t sp = H5Dget_space(ds);
    hsize_t dims[2] = {0, 1};
    const int nd = H5Sget_simple_extent_dims(sp, dims, nullptr);
    v.resize(static_cast<std::size_t>(dims[0] * (nd == 2 ? dims[1] : 1)));
    H5Dread(ds, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, v.data());
    H5Sclose(sp);
    H5Dclose(ds);
  }
  H5Fclose(f);
  return v;
}
// The elastic block in the die to 1 % strain with three snapshots (t = 0, T/2, T), written to `dir`.
Scene<2> block_with_snapshots(const fs::path& dir, RunOptions& o) {
  fs::remove_all(dir);
  std::string deck = test::block_deck(100, 0.01);
  deck.replace(deck.find("snapshots = 0"), 13, "snapshots = 2");
  o = test::quiet();
  o.out_dir = dir.string();
  return test::scene_from(deck);
}
}  // namespace

TEST(Snapshots, RigidBodiesAreWrittenBesideTheSpecimen) {
  const fs::path dir = fs::temp_directory_path() / ("pbx_test_snapshots_" + std::to_string(::getpid()));
  RunOptions o;
  Scene<2> sc = block_with_snapshots(dir, o);
  std::size_t rigid = 0, punch_first = 0, punch_count = 0;
  for (std::size_t b = 0; b < sc.bodies.size(); ++b) {
    if (sc.bodies[b].name == "punch") {
      punch_first = rigid;
      punch_count = sc.bodies[b].x.size();
    }
    rigid += sc.bodies[b].x.size();
  }
  ASSERT_GT(punch_count, 0u);
  double punch_y_end = 0;
  {
    Runner<2> r(sc, o);
    r.run();
    for (const auto& b : sc.bodies)
      if (b.name == "punch") punch_y_end = b.x.front()[1];
  }
  const std::string xmf = test::slurp((dir / "snapshots" / "snapshots.xmf").string());
  std::size_t grids = 0;
  for (auto at = xmf.find("<Grid Name=\"rigid_bodies\""); at != std::string::npos;
       at = xmf.find("<Grid Name=\"rigid_bodies\"", at + 1))
    ++grids;
  EXPECT_EQ(grids, 3u) << xmf;  // snapshots at t = 0, T/2, T
  const auto pos = read_doubles((dir / "snapshots" / "snap_0002.h5").string(), "rigid_position");
  ASSERT_EQ(pos.size(), 3 * rigid);
  EXPECT_DOUBLE_EQ(pos[3 * punch_first + 1], punch_y_end);
  const auto pos0 = read_doubles((dir / "snapshots" / "snap_0000.h5").string(), "rigid_position");
  ASSERT_EQ(pos0.size(), 3 * rigid);
  // the punch moved down by the stroke (1 % of 0.48 mm), the walls not at all
  EXPECT_NEAR(pos0[3 * punch_first + 1] - pos[3 * punch_first + 1], 0.01 * 0.48e-3, 1e-12);
  EXPECT_EQ(pos0[1], pos[1]);
  fs::remove_all(dir);
}

// The specimen's datasets read back equal the particles' state at that time, component by
// component (XDMF Tensor6 order xx, xy, xz, yy, yz, zz; pressure -tr/3; von Mises; volume; z = 0 in
// 2-D): a writer that swapped two components or wrote another particle's values would differ. The
// block in the die has sxx != syy != szz, so every diagonal slot is told apart.
TEST(Snapshots, ParticleDatasetsReadBackAsTheParticlesState) {
  const fs::path dir = fs::temp_directory_path() / ("pbx_test_snapshots_state_" + std::to_string(::getpid()));
  RunOptions o;
  Scene<2> sc = block_with_snapshots(dir, o);
  {
    Runner<2> r(sc, o);
    r.run();
  }
  const std::string snap = (dir / "snapshots" / "snap_0002.h5").string();  // t = end: the state after run()
  const auto stress = read_doubles(snap, "stress"), pressure = read_doubles(snap, "pressure"),
             mises = read_doubles(snap, "von_mises"), volume = read_doubles(snap, "volume"),
             pos = read_doubles(snap, "position");
  const auto& P = sc.particles;
  const std::size_t n = P.size();
  ASSERT_EQ(stress.size(), 6 * n);
  ASSERT_EQ(pos.size(), 3 * n);
  ASSERT_EQ(volume.size(), n);
  ASSERT_EQ(pressure.size(), n);
  ASSERT_EQ(mises.size(), n);
  double sxx = 0, syy = 0;
  for (std::size_t p = 0; p < n; ++p) {
    const Sym3& s = P.stress[p];
    const double want[6] = {s.xx, s.xy, s.zx, s.yy, s.yz, s.zz};
    for (int c = 0; c < 6; ++c) ASSERT_EQ(stress[6 * p + c], want[c]) << "particle " << p << " component " << c;
    ASSERT_EQ(pos[3 * p], P.x[p][0]);
    ASSERT_EQ(pos[3 * p + 1], P.x[p][1]);
    ASSERT_EQ(pos[3 * p + 2], 0.0);
    ASSERT_EQ(volume[p], P.volume[p]);
    ASSERT_DOUBLE_EQ(pressure[p], -s.trace() / 3);
    ASSERT_DOUBLE_EQ(mises[p], s.von_mises());
    sxx += s.xx;
    syy += s.yy;
  }
  EXPECT_LT(syy, 1.5 * sxx) << "the die block is compressed more along y than x";  // both negative
  fs::remove_all(dir);
}
