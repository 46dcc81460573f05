// Restart bit-identity beyond the default path (issue 29: "restart of plastic, viscoelastic and EOS
// history variables, of other integrators, of contact runs and of snapshot series"): a two-grain
// die specimen with the paper's laws (TATB J2 + Mie-Grueneisen with a low yield stress so that it
// flows, F2314 Prony + Tait), contact between the fields (Coulomb, a binder-layer spring between the
// grains) and with the walls (friction), and a snapshot series. For each integrator (USF, USL, MUSL)
// and a FLIP/PIC blend of 0.5, a run resumed from its mid-run checkpoint must write the uninterrupted run's history.csv
// byte for byte and the same snapshot series (times and particle counts in the XDMF sidecar). Independent expected
// value: the uninterrupted run itself; a state the checkpoint forgot (a history variable, the layer law's bonds, the
// FLIP velocities, USF's last contact velocities) changes some digit.
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include <fmt/format.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include "../deck_parts.hpp"
#include "../materials/material_fixtures.hpp"
#include "io/checkpoint.hpp"
#include "io/json.hpp"
#include "scene_fixture.hpp"

namespace fs = std::filesystem;
using namespace pbx;

namespace {
std::string deck_for(const std::string& integrator, double flip, const std::string& film) {
  // the paper's TATB (material_fixtures.hpp) with a yield stress low enough to flow in this run
  std::string tatb = "[materials.tatb]" + test::tatb_body;
  const std::string paper_yield = "yield_stress = \"0.80 GPa\"";
  tatb.replace(tatb.find(paper_yield), paper_yield.size(), "yield_stress = \"20 MPa\"");
  const std::string contact = R"(
[contact]
default = "coulomb"
friction = 0.3
[[contact.pair]]
materials = ["tatb", "tatb"]
law = "binder_layer"
friction = 0.3
binder = "f2314"
thickness = "4 um"
)" + (film.empty() ? std::string() : "film = \"" + film + "\"\n");
  return R"(
[run]
end_strain = 0.006
history_points = 60
snapshots = 4
[grid]
cell_size = "10 um"
[solver]
mass_scaling = 100
integrator = ")" +
         integrator + R"("
flip = )" +
         std::to_string(flip) +
         R"(
[die]
width = "0.2 mm"
height = "0.24 mm"
punch_velocity = "0.3 m/s"
ramp_strain = 0.001
wall_friction = 0.3
)" + tatb +
         "[materials.f2314]" + test::f2314_body + R"(
)" + test::two_grains_in_binder(0.047, "tatb", "f2314") +
         contact;
}

std::string slurp(const fs::path& p) {
  std::ifstream f(p, std::ios::binary);
  std::stringstream ss;
  ss << f.rdbuf();
  return ss.str();
}

void check_restart(const std::string& integrator, double flip, const std::string& film = "") {
  const fs::path dir =
      fs::temp_directory_path() / fmt::format("pbxmpm_restart_paths_{}_{}_{}{}", ::getpid(), integrator, flip, film);
  fs::remove_all(dir);
  const std::string deck = deck_for(integrator, flip, film);
  RunOptions o = test::quiet();
  o.out_dir = (dir / "a").string();
  o.deck_text = deck;
  o.deck_name = "two_grains";
  o.checkpoint_every = 25;  // rows 25 and 50 of 61: the file keeps row 50, after two snapshots
  std::size_t pairs = 0;
  double pairs_a_over_t = 0;
  {
    Scene<2> sc = test::scene_from(deck);
    for (const auto& b : sc.layer_data.bonds) ++pairs, pairs_a_over_t += b.coef;
    Runner<2> r(sc, o);
    r.run();
  }
  ASSERT_TRUE(fs::exists(dir / "a" / "checkpoint.h5"));
  // run.json states the film the pairs carry (film = "bonds" only): the scene's own pairs
  {
    const Json spec = json_read_file((dir / "a" / "run.json").string())["specimen"];
    if (film == "bonds") {
      ASSERT_GT(pairs, 0u);
      ASSERT_NE(json_find(spec, "film_pairs"), nullptr);
      EXPECT_EQ(json_number(spec["film_pairs"]), static_cast<double>(pairs));
      EXPECT_DOUBLE_EQ(json_number(spec["film_pairs_sum_a_over_t"]), pairs_a_over_t);
      EXPECT_GE(json_number(spec["film_gap_binder_particles_joined"]), 0.0);
    } else {
      EXPECT_EQ(json_find(spec, "film_pairs"), nullptr);
    }
  }
  const CheckpointData c = read_checkpoint((dir / "a" / "checkpoint.h5").string());
  // the interrupted copy: the run's folder as the checkpoint left it (history and snapshots beyond
  // the checkpoint are there too, as after a kill; the restart must cut and rewrite them)
  fs::copy(dir / "a", dir / "b", fs::copy_options::recursive);
  {
    Scene<2> sc = test::scene_from(c.deck_text);
    RunOptions ob = o;
    ob.out_dir = (dir / "b").string();
    ob.checkpoint_every = 0;
    Runner<2> r(sc, ob, true);
    r.resume(c);
    r.run();
  }
  const std::string ha = slurp(dir / "a" / "history.csv"), hb = slurp(dir / "b" / "history.csv");
  EXPECT_EQ(ha, hb) << integrator << " flip " << flip;
  EXPECT_EQ(slurp(dir / "a" / "snapshots" / "snapshots.xmf"), slurp(dir / "b" / "snapshots" / "snapshots.xmf"))
      << integrator << " flip " << flip;
  // the run did what it is here to test: energy dissipated (plastic, viscous, frictional), the
  // binder-layer springs and the grain-grain contact loaded at the end
  auto last = [&](const std::string& column) {
    std::istringstream in(ha);
    std::string header, line, row, cell;
    std::getline(in, header);
    while (std::getline(in, line)) row = line;
    std::istringstream h(header), r(row);
    while (std::getline(h, cell, ',')) {
      std::string value;
      std::getline(r, value, ',');
      if (cell == column) return std::stod(value);
    }
    ADD_FAILURE() << "no column " << column;
    return 0.0;
  };
  EXPECT_GT(last("dissipated_J_per_m"), 0.02 * last("internal_J_per_m")) << integrator;  // 25 % (usf, usl, musl)
  // (with film = "bonds" the pairs carry the grains' film and the nodes leave them alone)
  if (film.empty()) {
    EXPECT_GT(last("contact_tatb_tatb_fn_N_per_m"), 0.0) << integrator;
  }
  EXPECT_GT(last("layer_energy_J_per_m"), 0.0) << integrator;
  // the dissipation's parts (history columns since 2026-12-06): each present, and together the
  // total to round-off; a part the checkpoint forgot restarts at zero and the byte check above fails
  const double tatb = last("dissipated_tatb_J_per_m"), f2314 = last("dissipated_f2314_J_per_m"),
               contact = last("contact_work_J_per_m"), total = last("dissipated_J_per_m");
  EXPECT_GT(tatb, 0.0) << integrator;     // J2 flow at 20 MPa
  EXPECT_GT(f2314, 0.0) << integrator;    // Prony relaxation
  EXPECT_GT(contact, 0.0) << integrator;  // friction of walls and grains at mu 0.3
  EXPECT_NEAR(tatb + f2314 + contact, total, 1e-9 * total) << integrator;
  EXPECT_GT(last("max_particle_speed_m_s"), 0.0) << integrator;
  if (!::testing::Test::HasFailure() && !std::getenv("PBX_KEEP")) fs::remove_all(dir);
}
}  // namespace

TEST(RestartPaths, UsfResumesBitForBit) { check_restart("usf", 0.99); }
TEST(RestartPaths, UslResumesBitForBit) { check_restart("usl", 0.99); }
TEST(RestartPaths, MuslResumesBitForBit) { check_restart("musl", 0.99); }
TEST(RestartPaths, HalfFlipResumesBitForBit) { check_restart("usl", 0.5); }
// film = "bonds": the pairs and the binder particles joined to a grain are rebuilt from the deck on
// restart and must match the checkpoint's particles (their fields are in its layout)
TEST(RestartPaths, ParticlePairFilmResumesBitForBit) { check_restart("usl", 0.99, "bonds"); }
