// The Hashin-Shtrikman phases of a run come from the run's own deck at its temperature and loading
// time: checked against closed forms (linear elastic K, G; Tait K0(T); the Prony relaxation modulus
// with the Arrhenius shift at the loading time of the middle of the linear window).
#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>

#include <gtest/gtest.h>

#include "io/json.hpp"
#include "core/error.hpp"
#include "study/run_phases.hpp"

using namespace pbx;
namespace fs = std::filesystem;

namespace {

const char* kDeck = R"(
[die]
width = '1.0 mm'
height = '1.2 mm'
punch_velocity = '0.3 m/s'
ramp_strain = 0.004

[materials.grain]
model = 'linear_elastic'
density = '1.9 g/cm3'
youngs_modulus = '1 GPa'
poisson_ratio = 0.25

[materials.binder]
model = 'viscoelastic_tait'
density = '2.02 g/cm3'
reference_temperature = '293 K'
shift = 'arrhenius'
activation_energy = '100 kJ/mol'
long_term_shear_modulus = '10 MPa'
prony_shear_moduli = ['12.5 MPa', '12.5 MPa', '12.5 MPa']
prony_shear_times = ['1e-3 s', '1e-2 s', '1e-1 s']
tait_c = 0.0894
tait_k0 = '0.27 GPa'
tait_b1 = '4e-3 1/K'
)";

StudyRun make_run(const std::string& name, const std::string& deck, const std::string& materials_json) {
  const fs::path dir = fs::temp_directory_path() / ("pbxmpm_run_phases_" + name);
  fs::create_directories(dir);
  std::ofstream(dir / "deck.toml") << deck;
  std::ofstream(dir / "run.json") << R"({"temperature_K": 333, "specimen": {"porosity": 0.1}, "materials": )"
                                  << materials_json << "}";
  StudyRun r;
  r.id = name;
  r.dir = dir.string();
  r.analysis = json_parse(R"({"linear_window": {"lo": 0.004, "hi": 0.02}})");
  return r;
}

const char* kMaterials = R"([{"name": "binder", "particles": 100}, {"name": "grain", "particles": 900}])";

}  // namespace

TEST(RunPhases, ModuliAtTheRunTemperatureAndLoadingTime) {
  const RunPhases rp = run_phases(make_run("closed_forms", kDeck, kMaterials));
  // Middle of the window 1.2 %, reached after the 0.4 % ramp (taking 2 x 0.4 % H / v): (1.2 + 0.4) % H / v.
  const double t = 0.016 * 1.2e-3 / 0.3;
  EXPECT_NEAR(rp.load_time_s, t, 1e-12 * t);
  EXPECT_EQ(rp.temperature_K, 333);
  ASSERT_EQ(rp.phases.size(), 3u);

  const Phase& b = rp.phases[0];
  EXPECT_EQ(b.name, "binder");
  const double aT = std::exp(100e3 / 8.31446261815324 * (1.0 / 333 - 1.0 / 293));
  double G = 10e6;
  for (double tau : {1e-3, 1e-2, 1e-1}) G += 12.5e6 * std::exp(-t / (tau * aT));
  // The middle branch has relaxed to 0.41 at t: a wrong loading time or shift moves G by percents.
  EXPECT_NEAR(b.shear_modulus, G, 1e-5 * G);
  const double K = 0.27e9 * std::exp(-4e-3 * 40);
  EXPECT_NEAR(b.bulk_modulus, K, 1e-5 * K);
  EXPECT_NEAR(b.volume_fraction, 0.09, 1e-12);

  const Phase& g = rp.phases[1];
  EXPECT_EQ(g.name, "grain");
  EXPECT_NEAR(g.bulk_modulus, 1e9 / 1.5, 1e-5 * 1e9);
  EXPECT_NEAR(g.shear_modulus, 0.4e9, 1e-5 * 0.4e9);
  EXPECT_NEAR(g.volume_fraction, 0.81, 1e-12);

  EXPECT_EQ(rp.phases[2].name, "pores");
  EXPECT_NEAR(rp.phases[2].volume_fraction, 0.1, 1e-12);
}

TEST(RunPhases, AMaterialMissingFromTheDeckIsNamed) {
  const StudyRun r = make_run("missing", kDeck, R"([{"name": "tatb", "particles": 10}])");
  try {
    run_phases(r);
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("'tatb'"), std::string::npos) << e.what();
  }
}

TEST(RunPhases, ARunWithoutALinearWindowIsNamed) {
  StudyRun r = make_run("no_window", kDeck, kMaterials);
  r.analysis = json_parse(R"({"porosity": 0.1})");
  std::string source;
  try {
    run_phases_for_bounds(r, source);
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("linear window"), std::string::npos) << e.what();
  }
}

// The loading time comes from the punch timing the run had: run.json's ramp, speed and height when
// it records them, else the deck's with the scene's default ramp (0.002). Before 2026-12-06 a deck
// without ramp_strain was read with a ramp of 0 here and 0.002 by the run.
TEST(RunPhases, LoadingTimeUsesThePunchTimingTheRunHad) {
  std::string deck = kDeck;
  deck.replace(deck.find("ramp_strain = 0.004\n"), 20, "");
  const RunPhases defaulted = run_phases(make_run("default_ramp", deck, kMaterials));
  const double t_default = (0.012 + 0.002) * 1.2e-3 / 0.3;
  EXPECT_NEAR(defaulted.load_time_s, t_default, 1e-12 * t_default);

  StudyRun run = make_run("recorded", kDeck, kMaterials);
  std::ofstream(fs::path(run.dir) / "run.json")
      << R"({"temperature_K": 333, "ramp_strain": 0.001, "punch_velocity_m_s": 0.6,)"
      << R"( "specimen": {"porosity": 0.1, "height_m": 0.0024}, "materials": )" << kMaterials << "}";
  const RunPhases recorded = run_phases(run);
  const double t_recorded = (0.012 + 0.001) * 2.4e-3 / 0.6;
  EXPECT_NEAR(recorded.load_time_s, t_recorded, 1e-12 * t_recorded);
}
