// Each class of bad deck gets its own clear message naming the key.
#include <gtest/gtest.h>

#include "block_deck.hpp"
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
      {"shape_function = \"ugimp\"", "shape_function = \"cubic\"", "grid.shape_function: unknown shape function 'cubic'"},
      {"end_strain = 0.04", "end_strain = 0.7", "run.end_strain: must lie in (0, 0.5)"},
      // a specimen reaching into the punch or a wall
      {"max = [\"0.04 mm\", \"0.48 mm\"]", "max = [\"0.04 mm\", \"0.58 mm\"]",
       "geometry[0].max: reaches outside the die cavity"},
      {"min = [\"0 mm\", \"0 mm\"]", "min = [\"-0.01 mm\", \"0 mm\"]", "geometry[0].min: reaches outside the die cavity"},
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
      {"material = \"block\"\n", "material = \"block\"\n[[geometry]]\nmin = [\"0 mm\", \"0 mm\"]\nmax = [\"0.02 mm\", \"0.02 mm\"]\nmaterial = \"block\"\n",
       "geometry[1].shape: this entry produced no particles"},
      // a rigid body may not take a die body's name (history columns and fields are named by it)
      {"material = \"block\"\n", "material = \"block\"\n[[rigid]]\nname = \"punch\"\nmin = [\"0 mm\", \"0.5 mm\"]\nmax = [\"0.04 mm\", \"0.51 mm\"]\nnormal = [0, -1]\n",
       "rigid[0].name: 'punch' is already the name"},
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
  deck += "[[rigid]]\nname = \"anvil\"\nmin = [\"0 mm\", \"0.1 mm\"]\nmax = [\"0.04 mm\", \"0.11 mm\"]\nnormal = [0, -1]\n";
  testing::internal::CaptureStderr();
  Deck d = Deck::from_string(deck, "test.toml");
  Scene<2> sc = build_scene<2>(d);
  const std::string err = testing::internal::GetCapturedStderr();
  EXPECT_NE(err.find("rigid body 'anvil' starts over 16 deformable particle(s)"), std::string::npos) << err;
}
