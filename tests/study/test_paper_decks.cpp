// Every study deck shipped in examples/paper reads, and every run it defines is a valid deck whose
// varied value reaches the built scene (checked per key, an ignored override fails): a
// mistyped override must fail here, not an hour into a study. Runs at the quick resolution are
// built in full (packing included); the fine and full decks differ from quick only in the cell
// size, so for them the run decks are parsed and their overrides checked against the base deck.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <utility>
#include <vector>

#include <gtest/gtest.h>
#include <unistd.h>

#include "../analysis/synthetic_run.hpp"
#include "analysis/run_analysis.hpp"
#include "contact/contact_matrix.hpp"
#include "io/deck.hpp"
#include "io/json.hpp"
#include "materials/point_driver.hpp"
#include "setup/build_scene.hpp"
#include "study/study.hpp"

using namespace pbx;

namespace {
const std::string kPaper = std::string(PBXMPM_EXAMPLES_DIR) + "/paper/";

// Von Mises stress at which a material point of the scene's material `name` flows in simple shear
// (to a shear strain of 0.2 at 250 /s): the yield stress the scene's law actually uses.
double flow_stress(const Scene<2>& sc, const std::string& name) {
  const auto it = std::find(sc.material_names.begin(), sc.material_names.end(), name);
  if (it == sc.material_names.end()) return std::nan("");
  MaterialPoint<2> mp(*sc.materials[static_cast<std::size_t>(it - sc.material_names.begin())]);
  Mat<2> L = Mat<2>::Zero();
  L(0, 1) = 250.0;
  for (int k = 0; k < 4000; ++k) mp.step(L, 0.2 / 250.0 / 4000);
  return mp.stress().von_mises();
}

// The value a run sets for each key a study of examples/paper varies reaches the built scene (an
// override that the builder ignored would leave the base deck's value): temperature, porosity of
// the packed specimen (within the packer's tolerance), TATB yield stress (by driving a material
// point of the scene's own law into flow), contact friction of every Coulomb pair, position check.
// Returns how many keys were checked.
int check_run_values(const Scene<2>& sc, const Deck& d, const StudyRunSpec& r, const std::string& at) {
  int checked = 0;
  const DeckTable root = d.root();
  for (const auto& kv : r.set) {
    const std::string& key = kv.first;
    if (key == "run.temperature") {
      EXPECT_NEAR(sc.control.temperature, root.table("run").positive("temperature", dim::temperature), 1e-9) << at;
    } else if (key == "packing.porosity") {
      EXPECT_TRUE(sc.packing_stats.has_value()) << at;
      if (sc.packing_stats) {
        EXPECT_NEAR(sc.packing_stats->porosity, root.table("packing").number("porosity"), 0.002) << at;
      }
    } else if (key == "materials.tatb.yield_stress") {
      const double y = root.table("materials").table("tatb").positive("yield_stress", dim::pressure);
      EXPECT_NEAR(flow_stress(sc, "tatb"), y, 0.01 * y) << at;
    } else if (key == "contact.friction") {
      const double mu = root.table("contact").number("friction");
      int pairs = 0;
      for (int a = 0; a < sc.deformable_fields; ++a)
        for (int b = a + 1; b < sc.deformable_fields; ++b)
          if (sc.contact(a, b).law == ContactLaw::coulomb) {
            EXPECT_EQ(sc.contact(a, b).friction, mu) << at << " fields " << a << ", " << b;
            ++pairs;
          }
      EXPECT_GT(pairs, 0) << at;
    } else if (key == "contact.position_check") {
      EXPECT_EQ(sc.contact.position_cutoff, root.table("contact").number("position_check")) << at;
    } else if (key == "contact.pair") {
      // the calibration's film law (calibrated.toml): its flow factor and coat scale reach the scene
      const auto pairs = root.table("contact").tables("pair");
      EXPECT_EQ(pairs.size(), sc.contact.layers.size()) << at;
      for (std::size_t k = 0; k < std::min(pairs.size(), sc.contact.layers.size()); ++k) {
        EXPECT_EQ(sc.contact.layers[k].flow_factor, pairs[k].number("flow_factor", 0.0)) << at;
        EXPECT_EQ(sc.contact.layers[k].coat_scale, pairs[k].number("coat_scale", 1.0)) << at;
      }
    } else if (key == "run.end_strain") {
      EXPECT_NEAR(sc.control.end_strain, root.table("run").number("end_strain"), 1e-15) << at;
    } else if (key == "grid.cell_size") {
      EXPECT_NEAR(sc.grid.h, root.table("grid").positive("cell_size", dim::length), 1e-15) << at;
    } else {
      continue;
    }
    ++checked;
  }
  EXPECT_GT(sc.particles.size(), 0u) << at;
  return checked;
}

void build_every_run(const std::string& deck) {
  const StudySpec s = read_study(kPaper + deck);
  ASSERT_FALSE(s.runs.empty()) << deck;
  for (const auto& r : s.runs) {
    Deck d = Deck::from_string(run_deck_text(s, r), deck + ":" + r.id);
    EXPECT_NO_THROW({
      Scene<2> scene = build_scene<2>(d);
      d.check_unused();
      // every run carries a value of its group's key (the key the study varies), and it is checked
      EXPECT_GE(check_run_values(scene, d, r, deck + " run " + r.id), 1) << deck << " run " << r.id;
    }) << deck
       << " run " << r.id;
  }
}
// The overrides of a run without those that set resolution and output only.
std::vector<std::pair<std::string, std::string>> physics_overrides(const StudyRunSpec& r) {
  std::vector<std::pair<std::string, std::string>> out;
  for (const auto& kv : r.set)
    if (kv.first != "grid.cell_size" && kv.first != "run.snapshots") out.push_back(kv);
  return out;
}
}  // namespace

TEST(PaperDecks, QuickStudyRunsAreValidDecks) { build_every_run("quick.toml"); }
TEST(PaperDecks, SensitivityStudyRunsAreValidDecks) { build_every_run("sensitivity.toml"); }
TEST(PaperDecks, ContactDetectionStudyRunsAreValidDecks) { build_every_run("contact_detection.toml"); }
TEST(PaperDecks, QuickGrainContactStudyRunsAreValidDecks) { build_every_run("quick_grain_contact.toml"); }
TEST(PaperDecks, QuickBondsStudyRunsAreValidDecks) { build_every_run("quick_bonds.toml"); }
TEST(PaperDecks, QuickJoinedStudyRunsAreValidDecks) { build_every_run("quick_joined.toml"); }
TEST(PaperDecks, LayerResolutionStudyRunsAreValidDecks) { build_every_run("layer_resolution.toml"); }
TEST(PaperDecks, CalibratedStudyRunsAreValidDecks) { build_every_run("calibrated.toml"); }

// The calibrated binder (calibrated.toml's F2314 Prony weights, re-distributed over the same times)
// keeps the default's secant shear modulus at 293 K and falls as 1 : 0.78 : 0.62 : 0.35 over 293 /
// 333 / 353 / 373 K (the deck's comment and docs/theory/paper_study.md 0.1): driven in simple shear
// at 250 /s to 2.5 % (100 us), as MaterialExamples.F2314CalibrationSoftensWithTemperature drives
// the default (1 : 0.61 : 0.45 : 0.31 would fail the 0.01 band at every temperature).
TEST(PaperDecks, CalibratedBinderFallsAsTableThree) {
  const StudySpec s = read_study(kPaper + "calibrated.toml");
  const double ratio[] = {1.0, 0.78, 0.62, 0.35};
  int n = 0;
  double g293 = 0;
  for (const auto& r : s.runs) {
    if (r.group != "temperature") continue;
    const Deck d = Deck::from_string(run_deck_text(s, r), "calibrated.toml:" + r.id);
    MaterialContext ctx;
    ctx.temperature = d.root().table("run").positive("temperature", dim::temperature);
    ctx.name = "f2314";
    auto m = make_material<3>(d.root().table("materials").table("f2314"), ctx);
    PointLoad load;
    load.path = PointPath::simple_shear, load.strain = 0.025, load.rate = 250.0, load.steps = 200;
    const double G = drive_point(*m, load).back().stress.xy / 0.025;
    if (n == 0) {
      g293 = G;
      EXPECT_NEAR(G, 68.6e6, 0.01 * 68.6e6) << r.id;  // the default calibration's value at 293 K
    }
    EXPECT_NEAR(G / g293, ratio[n], 0.01) << r.id;
    ++n;
  }
  EXPECT_EQ(n, 4);
}

// The calibrated study's density runs go on past 99 % of the theoretical density (the paper's Fig. 7
// reads 42.3 MPa there): in the die that is strain 1 - (1 - porosity) / 0.99 (the packer meets the
// porosity within 0.002, CalibratedStudyRunsAreValidDecks); every run's film law flows. Read from
// the run decks (the scenes are built by the test above).
TEST(PaperDecks, CalibratedDensityRunsReachNinetyNinePercentTmd) {
  const StudySpec s = read_study(kPaper + "calibrated.toml");
  int density = 0;
  for (const auto& r : s.runs) {
    const Deck d = Deck::from_string(run_deck_text(s, r), "calibrated.toml:" + r.id);
    const DeckTable root = d.root();
    EXPECT_GT(root.table("contact").tables("pair").at(0).number("flow_factor", 0.0), 0.0) << r.id;
    if (r.group != "density") continue;
    ++density;
    const double e99 = 1.0 - (1.0 - root.table("packing").number("porosity")) / 0.99;
    EXPECT_GT(root.table("run").number("end_strain"), e99 + 0.003) << r.id;
  }
  EXPECT_EQ(density, 9);
}

// quick.toml's runs of seed 1 (it runs the densities over three seeds, the finer studies over one).
std::vector<StudyRunSpec> seed_one(const StudySpec& s) {
  std::vector<StudyRunSpec> out;
  for (const auto& r : s.runs)
    if (r.seed == 1) out.push_back(r);
  return out;
}

TEST(PaperDecks, QuickRunsThreeSeedsPerDensityAndOnePerTemperature) {
  const StudySpec quick = read_study(kPaper + "quick.toml");
  int temperature = 0, density = 0;
  for (const auto& r : quick.runs) (r.group == "temperature" ? temperature : density) += 1;
  EXPECT_EQ(temperature, 4);
  EXPECT_EQ(density, 9);
  for (const long seed : {1L, 2L, 3L})
    EXPECT_EQ(std::count_if(quick.runs.begin(), quick.runs.end(),
                            [&](const StudyRunSpec& r) { return r.group == "density" && r.seed == seed; }),
              3)
        << seed;
}

TEST(PaperDecks, FineAndFullDifferFromQuickOnlyInResolution) {
  StudySpec quick = read_study(kPaper + "quick.toml");
  quick.runs = seed_one(quick);
  for (const std::string name : {"fine.toml", "full.toml"}) {
    const StudySpec s = read_study(kPaper + name);
    ASSERT_EQ(s.runs.size(), quick.runs.size()) << name;
    for (std::size_t i = 0; i < s.runs.size(); ++i) {
      EXPECT_EQ(s.runs[i].id, quick.runs[i].id) << name;
      EXPECT_EQ(physics_overrides(s.runs[i]), physics_overrides(quick.runs[i])) << name << " " << s.runs[i].id;
    }
    EXPECT_EQ(s.analysis.window_lo, quick.analysis.window_lo) << name;
    EXPECT_EQ(s.analysis.window_hi, quick.analysis.window_hi) << name;
  }
}

TEST(PaperDecks, EnsembleIsTheQuickStudyOverFiveSeeds) {
  // ensemble.toml must stay the quick study (its seed-1 runs are quick's runs) with seeds 1-5 and
  // the same linear window; only snapshots may differ.
  StudySpec quick = read_study(kPaper + "quick.toml");
  quick.runs = seed_one(quick);
  const StudySpec ens = read_study(kPaper + "ensemble.toml");
  ASSERT_EQ(ens.runs.size(), 5 * quick.runs.size());
  for (const auto& q : quick.runs) {
    int seeds = 0;
    for (const auto& r : ens.runs) {
      if (r.group != q.group || r.value_label != q.value_label) continue;
      ++seeds;
      auto strip_seed = [](std::vector<std::pair<std::string, std::string>> v) {
        std::erase_if(v, [](const auto& kv) { return kv.first == "specimen.seed"; });
        return v;
      };
      EXPECT_EQ(strip_seed(physics_overrides(r)), strip_seed(physics_overrides(q))) << r.id;
    }
    EXPECT_EQ(seeds, 5) << q.id;
  }
  EXPECT_EQ(ens.analysis.window_lo, quick.analysis.window_lo);
  EXPECT_EQ(ens.analysis.window_hi, quick.analysis.window_hi);
}

// The paper decks measure the paper's linear stage: a history shaped like the paper's own curve
// (Table 2 at 293 K, M = K + 4G/3 up to the knee at 0.65 %, then Eq. 14), sampled as the decks
// sample (their ramp, end strain and history points) and analysed with the study's [analysis]
// table, gives back Table 2's K, G, E within 2 %. The decks' earlier window [0.4 %, 2 %] with a
// 0.4 % ramp returned E = 0.49 GPa here instead of 3.38 (the fit lay on the plateau).
TEST(PaperDecks, StudiesReadThePapersLinearStage) {
  for (const std::string name : {"quick.toml", "fine.toml", "full.toml", "ensemble.toml"}) {
    const StudySpec s = read_study(kPaper + name);
    const Deck d = Deck::from_string(run_deck_text(s, s.runs.front()), name);
    test::SyntheticRun syn;  // defaults: Table 2 at 293 K on Eq. 14
    syn.ramp_strain = d.root().table("die").number("ramp_strain");
    syn.max_strain = d.root().table("run").number("end_strain");
    syn.rows = static_cast<int>(d.root().table("run").integer("history_points")) + 1;
    syn.vol_bias = 0.0;
    const auto dir = std::filesystem::temp_directory_path() / ("pbx_paper_window_" + std::to_string(::getpid()));
    std::filesystem::remove_all(dir);
    test::write_synthetic_run(dir, syn);
    const Json a = analyze_run(dir.string(), s.analysis);
    const Json& m = *json_find(a, "moduli");
    const double E = 9 * syn.K * syn.G / (3 * syn.K + syn.G);
    EXPECT_NEAR(json_number(*m.find("K_isotropic_Pa")) / syn.K, 1.0, 0.02) << name;
    EXPECT_NEAR(json_number(*m.find("G_Pa")) / syn.G, 1.0, 0.02) << name;
    EXPECT_NEAR(json_number(*m.find("E_Pa")) / E, 1.0, 0.02) << name;
    std::filesystem::remove_all(dir);
  }
}

// The calibration's claim, run (a slow test: about 75 s): the calibrated study's 293 K run (20 um
// cells, to 3.5 % strain) reads Table 3's 32.8 MPa within 15 % (measured 32.9 MPa on 2026-12-06
// with flow_factor 0.58 and the films' impulses through the particles; 0.55 read 31.7 and 0.62 34.5)
// and nearly conserves energy ((KE + stress work)/punch work at most 1.13 from the window's start;
// the faithful deck reaches 2.2, the first fit with the impulses at the node 3.2). The change of
// the films' transfer that afternoon moved this number by 8 % without a test noticing: a change of
// the film law, the transfer or the binder that moves the calibration fails here.
TEST(PaperDecks, CalibratedRunReadsTableThreeAt293K) {
  namespace fs = std::filesystem;
  const fs::path dir = fs::temp_directory_path() / ("pbxmpm_calibrated_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  const std::string cmd = std::string(PBXMPM_BINARY) + " study " + kPaper + "calibrated.toml --out " + dir.string() +
                          " --only temperature-293K-s1 --threads 1 --quiet --no-report > " + dir.string() + ".log 2>&1";
  if (std::system(cmd.c_str()) != 0) {
    std::ifstream log(dir.string() + ".log");
    FAIL() << cmd << "\n" << std::string(std::istreambuf_iterator<char>(log), {});
  }
  const Deck deck = Deck::from_file((dir / "analysis.toml").string());  // the tables below refer into it
  const DeckTable options = deck.root().table("analysis");
  const Json a = analyze_run((dir / "runs" / "temperature-293K-s1").string(), AnalysisOptions::from_deck(options));
  const double strength = json_number(*json_find(*json_find(a, "strength"), "strength_Pa"));
  const double energy = json_number(*json_find(*json_find(a, "energy_balance"), "max_ratio"));
  std::fprintf(stderr, "calibrated 293 K: strength %.2f MPa (Table 3: 32.8), energy ratio at most %.3f\n",
               strength / 1e6, energy);
  EXPECT_NEAR(strength, 32.8e6, 0.15 * 32.8e6);  // the band around Table 3
  // and the calibration as fitted, to 3 %: flow_factor 0.55 / 0.62 read 31.7 / 34.5 MPa, inside the band
  EXPECT_NEAR(strength, 32.88e6, 0.03 * 32.88e6);
  EXPECT_LT(energy, 1.2);
  fs::remove_all(dir);
  fs::remove(dir.string() + ".log");
}
