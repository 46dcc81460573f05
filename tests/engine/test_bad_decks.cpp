// Each class of bad deck gets its own clear message naming the key.
#include <cmath>

#include <gtest/gtest.h>

#include "../deck_parts.hpp"
#include "block_deck.hpp"
#include "setup/build_scene.hpp"
#include "core/error.hpp"
#include "scene_fixture.hpp"

using namespace pbx;

namespace {
std::string error_of(const std::string& deck) {
  try {
    test::scene_from(deck);
  } catch (const InputError& e) {
    return e.what();
  }
  return "(no error)";
}
std::string replace(std::string s, const std::string& a, const std::string& b) {
  const auto pos = s.find(a);
  EXPECT_NE(pos, std::string::npos) << a;
  if (pos != std::string::npos) s.replace(pos, a.size(), b);
  return s;
}
}  // namespace

TEST(BadDecks, EachClassNamesItsKey) {
  const std::string ok = test::block_deck(100);
  EXPECT_EQ(error_of(ok), "(no error)");
  struct Case {
    std::string from, to, expect;
  };
  const Case cases[] = {
      {"cfl = 0.4", "cfl = 1.2", "solver.cfl: must lie in (0, 1)"},
      {"cfl = 0.4", "cfll = 0.4", "unknown key 'solver.cfll'"},
      {"density = \"1.934 g/cm3\"", "density = \"-1.934 g/cm3\"", "materials.block.density: must be > 0"},
      {"shear_modulus = \"11.5 GPa\"", "shear_modulus = \"-11.5 GPa\"", "materials.block.shear_modulus: must be > 0"},
      {"shear_modulus = \"11.5 GPa\"", "shear_modulus = \"11.5 m/s\"", "materials.block.shear_modulus"},
      {"bulk_modulus = \"10.59 GPa\"\n", "", "materials.block.bulk_modulus: required key missing"},
      {"model = \"linear_elastic\"", "model = \"rubber\"", "unknown material model 'rubber'"},
      {"material = \"block\"", "material = \"steel\"", "no material named 'steel'"},
      {"cell_size = \"10 um\"", "cell_size = \"7 um\"", "die.width: must be a whole number of cells"},
      {"mass_scaling = 100", "mass_scaling = 0.5", "solver.mass_scaling: must be >= 1"},
      {"mass_scaling = 100", "mass_scaling = \"fast\"", "solver.mass_scaling"},
      {"integrator = \"usl\"", "integrator = \"rk4\"", "unknown integrator 'rk4'"},
      {"shape_function = \"ugimp\"", "shape_function = \"cubic\"",
       "grid.shape_function: unknown shape function 'cubic'"},
      {"end_strain = 0.04", "end_strain = 0.7", "run.end_strain: must lie in (0, 0.5)"},
      // a specimen reaching into the punch or a wall
      {"max = [\"0.04 mm\", \"0.48 mm\"]", "max = [\"0.04 mm\", \"0.58 mm\"]",
       "geometry[0].max: reaches outside the die cavity"},
      {"min = [\"0 mm\", \"0 mm\"]", "min = [\"-0.01 mm\", \"0 mm\"]",
       "geometry[0].min: reaches outside the die cavity"},
      // toml's nan and inf are numbers: every quantity must be finite (inf passed every "> 0")
      {"density = \"1.934 g/cm3\"", "density = nan", "materials.block.density: must be a finite number"},
      {"shear_modulus = \"11.5 GPa\"", "shear_modulus = inf", "materials.block.shear_modulus: must be a finite number"},
      {"mass_scaling = 100", "mass_scaling = inf", "solver.mass_scaling: must be a finite number"},
      {"cfl = 0.4", "cfl = 0.4\ngravity = [nan, 0]", "solver.gravity: entry 0 must be a finite number"},
      // integers that size something are range-checked before any cast (2^32 + 200 was 200)
      {"history_points = 201", "history_points = 4294967496", "run.history_points: must lie in [2, 10000000]"},
      {"particles_per_cell = 2", "particles_per_cell = 4294967298", "grid.particles_per_cell: must lie in [1, 8]"},
      // a grid no machine holds is refused before anything is allocated
      {"cell_size = \"10 um\"", "cell_size = \"1 nm\"", "more than this machine's"},
      // a geometry entry that seeds nothing is an error, not a missing body
      {"material = \"block\"\n",
       "material = \"block\"\n[[geometry]]\nmin = [\"0 mm\", \"0 mm\"]\nmax = [\"0.02 mm\", \"0.02 mm\"]\nmaterial = "
       "\"block\"\n",
       "geometry[1].shape: this entry produced no particles"},
      // a rigid body may not take a die body's name (history columns and fields are named by it)
      {"material = \"block\"\n",
       "material = \"block\"\n[[rigid]]\nname = \"punch\"\nmin = [\"0 mm\", \"0.5 mm\"]\nmax = [\"0.04 mm\", \"0.51 "
       "mm\"]\nnormal = [0, -1]\n",
       "rigid[0].name: 'punch' is already the name"},
      // the contact face's normal is required, not zero by default (which read "must be a unit vector")
      {"material = \"block\"\n",
       "material = \"block\"\n[[rigid]]\nname = \"anvil\"\nmin = [\"0 mm\", \"0.5 mm\"]\nmax = [\"0.04 mm\", \"0.51 "
       "mm\"]\n",
       "rigid[0].normal: required key missing"},
  };
  for (const auto& c : cases) {
    const std::string msg = error_of(replace(ok, c.from, c.to));
    EXPECT_NE(msg.find(c.expect), std::string::npos) << "expected '" << c.expect << "' in: " << msg;
  }
}

// A unilateral rigid body placed over deformable particles is stated (count and first particle),
// not refused (the Hertz test uses a plate over half a disk as its symmetry plane).
TEST(BadDecks, RigidBodyOverParticlesIsStated) {
  std::string deck = test::block_deck(100);
  deck +=
      "[[rigid]]\nname = \"anvil\"\nmin = [\"0 mm\", \"0.1 mm\"]\nmax = [\"0.04 mm\", \"0.11 mm\"]\nnormal = [0, -1]\n";
  testing::internal::CaptureStderr();
  Deck d = Deck::from_string(deck, "test.toml");
  Scene<2> sc = build_scene<2>(d);
  const std::string err = testing::internal::GetCapturedStderr();
  EXPECT_NE(err.find("rigid body 'anvil' starts over 16 deformable particles"), std::string::npos) << err;
}

// A rigid disk is filled as a disk: its particle count is that of the disk (pi r^2 / spacing^2),
// not of its bounding square (4/pi = 1.27 times more), which is what it was before.
TEST(RigidBodies, DiskIsFilledAsADisk) {
  const std::string deck = R"(
[run]
end_time = "1 us"
snapshots = 0
[grid]
cell_size = "10 um"
min = ["-0.05 mm", "-0.05 mm"]
max = ["0.45 mm", "0.45 mm"]
)" + test::elastic("disk", 2.0, 1, 0.3) +
                           test::box_mm(0, 0, 0.1, 0.1, "disk") + R"(
[[rigid]]
name = "roller"
shape = "disk"
center = ["0.25 mm", "0.25 mm"]
radius = "0.1 mm"
normal = [0, -1]
)";
  Scene<2> sc = test::scene_from(deck);
  ASSERT_EQ(sc.bodies.size(), 1u);
  const auto& b = sc.bodies[0];
  const double spacing = 10e-6 / 2;  // 2 x 2 particles per cell
  const double disk = M_PI * 1e-4 * 1e-4 / (spacing * spacing);
  EXPECT_NEAR(static_cast<double>(b.x0.size()), disk, 0.02 * disk);
  for (const auto& x : b.x0) EXPECT_LE((x - Vec<2>(0.25e-3, 0.25e-3)).norm(), 1e-4 * (1 + 1e-12));
}

// specimen.seed with specimen.packing_dir is an error naming the key: a read packing has no seed.
TEST(BadDecks, SpecimenSeedWithAPackingDirIsRefused) {
  const std::string deck = R"(
[run]
end_strain = 0.01
snapshots = 0
[grid]
cell_size = "20 um"
[die]
width = "1.0 mm"
height = "1.2 mm"
punch_velocity = "0.3 m/s"
[materials.tatb]
model = "linear_elastic"
density = "1.934 g/cm3"
bulk_modulus = "10 GPa"
shear_modulus = "10 GPa"
[materials.f2314]
model = "linear_elastic"
density = "2.02 g/cm3"
bulk_modulus = "1 GPa"
shear_modulus = "0.1 GPa"
[specimen]
grain_material = "tatb"
binder_material = "f2314"
packing_dir = "no_such_dir"
seed = 3
)";
  const std::string msg = error_of(deck);
  EXPECT_NE(msg.find("specimen.seed: has no effect with specimen.packing_dir"), std::string::npos) << msg;
}
