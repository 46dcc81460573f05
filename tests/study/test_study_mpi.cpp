// A study run under `mpirun -n 2` gives the same results as the sequential run (each rank runs
// whole runs; the engine is deterministic: histories, analyses and study fits alike), resumes by skipping finished
// runs, and names bad keys.
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <vector>

#include <sys/wait.h>
#include <unistd.h>

#include <fmt/format.h>
#include <gtest/gtest.h>
#include <toml++/toml.h>

#include "core/error.hpp"
#include "setup/build_scene.hpp"
#include "io/json.hpp"
#include "io/deck.hpp"
#include "microstructure/packing.hpp"
#include "run/runner.hpp"
#include "study/study.hpp"
#include "study/study_status.hpp"

namespace fs = std::filesystem;
using namespace pbx;

namespace {
std::string slurp(const fs::path& p) {
  std::ifstream f(p);
  std::stringstream ss;
  ss << f.rdbuf();
  return ss.str();
}

fs::path make_study(const std::string& extra = "", const std::string& values = "[10, 20]") {
  // pid and test name, emptied first: /tmp outlives a run, and a later run with the same pid found
  // "finished" runs of an earlier one
  const fs::path dir = fs::temp_directory_path() / ("pbxmpm_study_" + std::to_string(::getpid()) + "_" +
                                                    ::testing::UnitTest::GetInstance()->current_test_info()->name());
  fs::remove_all(dir);
  fs::create_directories(dir);
  std::string base = slurp(fs::path(PBXMPM_EXAMPLES_DIR) / "demo" / "elastic_block_die.toml");
  auto set = [&](const std::string& from, const std::string& to) {
    const auto pos = base.find(from);
    ASSERT_NE(pos, std::string::npos) << from;
    base.replace(pos, from.size(), to);
  };
  set("end_strain = 0.01", "end_strain = 0.006");
  set("snapshots = 5", "snapshots = 0");
  set("cell_size = \"20 um\"", "cell_size = \"50 um\"");
  std::ofstream(dir / "base.toml") << base;
  std::ofstream(dir / "study.toml") << "[study]\nname = \"mpi-check\"\nbase = \"base.toml\"\n"
                                    << extra
                                    << "[[study.group]]\nname = \"scaling\"\nkey = \"solver.mass_scaling\"\n"
                                       "values = "
                                    << values << "\n";
  return dir;
}

// The error reading dir/study.toml gives, or "(no error)".
std::string error_of(const fs::path& dir) {
  try {
    read_study((dir / "study.toml").string());
  } catch (const InputError& e) {
    return e.what();
  }
  return "(no error)";
}

// Makes run `r` of study `s` in `run_dir` as a study would, writing a checkpoint every 5 history
// rows, and stops it (an exception) after `rows` rows: an interrupted run.
void interrupt_run(const StudySpec& s, const StudyRunSpec& r, const fs::path& run_dir, int rows) {
  fs::create_directories(run_dir);
  const std::string text = run_deck_text(s, r);
  std::ofstream(run_dir / "deck.toml") << text;
  Deck deck = Deck::from_file((run_dir / "deck.toml").string());
  Scene<2> scene = build_scene<2>(deck);
  RunOptions ro;
  ro.out_dir = run_dir.string();
  ro.progress = false;
  ro.deck_text = text;
  ro.deck_name = (run_dir / "deck.toml").string();
  ro.checkpoint_every = 5;
  Runner<2> runner(scene, ro);
  int made = 0;
  EXPECT_THROW(runner.run([&](const Measurement&) {
    if (++made == rows) throw std::runtime_error("stopped");
  }),
               std::runtime_error);
}
}  // namespace

TEST(Study, MpiTwoRanksEqualsSequentialAndResumes) {
  const fs::path dir = make_study();
  StudyOptions o;
  o.out_dir = (dir / "seq").string();
  o.report = false;
  o.progress = false;
  const StudySpec s = read_study((dir / "study.toml").string());
  ASSERT_EQ(s.runs.size(), 2u);
  EXPECT_EQ(run_study(s, o), 0);
  for (const auto& r : s.runs) ASSERT_TRUE(fs::exists(dir / "seq" / "runs" / r.id / "analysis.json")) << r.id;
  // resume: a second call skips both runs and leaves their files untouched
  const auto stamp = fs::last_write_time(dir / "seq" / "runs" / s.runs[0].id / "history.csv");
  EXPECT_EQ(run_study(s, o), 0);
  EXPECT_EQ(fs::last_write_time(dir / "seq" / "runs" / s.runs[0].id / "history.csv"), stamp);
  // a finished run made from another deck is not reused: the study fails and leaves it alone
  {
    const fs::path deck = dir / "seq" / "runs" / s.runs[0].id / "deck.toml";
    const std::string good = slurp(deck);
    std::string changed = good;
    const auto pos = changed.find("end_strain");
    ASSERT_NE(pos, std::string::npos);
    changed.insert(pos, "# edited\n");
    std::ofstream(deck) << changed;
    EXPECT_EQ(run_study(s, o), kStudyNotStarted);
    EXPECT_EQ(fs::last_write_time(dir / "seq" / "runs" / s.runs[0].id / "history.csv"), stamp);
    std::ofstream(deck) << good;
    EXPECT_EQ(run_study(s, o), 0);
  }

#ifndef PBXMPM_HAVE_MPI
  GTEST_SKIP() << "built without MPI (-DPBXMPM_WITH_MPI=OFF)";
#endif
  if (std::system("command -v mpirun > /dev/null 2>&1") != 0) GTEST_SKIP() << "mpirun not installed";
  const std::string cmd = "OMP_NUM_THREADS=1 mpirun --allow-run-as-root --oversubscribe -n 2 " +
                          std::string(PBXMPM_BINARY) + " study " + (dir / "study.toml").string() + " --out " +
                          (dir / "mpi").string() + " --quiet --no-report > " + (dir / "mpi.log").string() + " 2>&1";
  ASSERT_EQ(std::system(cmd.c_str()), 0) << slurp(dir / "mpi.log");
  for (const auto& r : s.runs) {
    EXPECT_EQ(slurp(dir / "seq" / "runs" / r.id / "history.csv"), slurp(dir / "mpi" / "runs" / r.id / "history.csv"))
        << r.id;
    // the two ranks each ran one run
  }
  EXPECT_NE(slurp(dir / "mpi.log").find("rank 1"), std::string::npos) << slurp(dir / "mpi.log");
  // ... and so do their analyses and the study's fits (per-condition statistics, fitted laws)
  for (const auto& r : s.runs) {
    const Json a = json_read_file((dir / "seq" / "runs" / r.id / "analysis.json").string());
    const Json b = json_read_file((dir / "mpi" / "runs" / r.id / "analysis.json").string());
    for (const char* key : {"moduli", "moduli_volume_average", "strength", "quasi_static", "linear_window"})
      EXPECT_EQ(json_dump(*json_find(a, key)), json_dump(*json_find(b, key))) << r.id << " " << key;
  }
  for (const char* study : {"seq", "mpi"}) {
    const std::string fit = fmt::format("'{}' fit study '{}' --out '{}' > /dev/null 2>&1", PBXMPM_BINARY,
                                        (dir / study).string(), (dir / (std::string(study) + "_fits.json")).string());
    ASSERT_EQ(std::system(fit.c_str()), 0) << fit;
  }
  const Json fa = json_read_file((dir / "seq_fits.json").string());
  const Json fb = json_read_file((dir / "mpi_fits.json").string());
  ASSERT_NE(json_find(fa, "conditions"), nullptr);
  EXPECT_EQ(json_dump(*json_find(fa, "conditions")), json_dump(*json_find(fb, "conditions")));
  EXPECT_EQ(json_dump(*json_find(fa, "density_law")), json_dump(*json_find(fb, "density_law")));
  fs::remove_all(dir);
}

TEST(Study, BadStudyDeckNamesTheKey) {
  const fs::path dir = make_study("colour = 3\n");
  try {
    read_study((dir / "study.toml").string());
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("study.colour"), std::string::npos) << e.what();
  }
  fs::remove_all(dir);
}

// Study decks that would make two runs out of one are refused before anything runs: the same
// value twice (one run folder for both), several seeds over a deck without a packed specimen
// (identical runs presented as an ensemble), and study seeds over a group that sets the seed
// itself (the study seed used to overwrite it, so every "seed" run was seed 1).
TEST(Study, DeckThatWouldMakeIdenticalRunsIsRefused) {
  fs::path dir = make_study("", "[10, 10]");
  EXPECT_NE(error_of(dir).find("get the same id 'scaling-10-s1'"), std::string::npos) << error_of(dir);
  fs::remove_all(dir);
  dir = make_study("seeds = [1, 2]\n");
  EXPECT_NE(error_of(dir).find("study.seeds: the base deck has no [specimen]"), std::string::npos) << error_of(dir);
  fs::remove_all(dir);
  dir = make_study();
  std::ofstream(dir / "study.toml") << "[study]\nname = \"seeds\"\nbase = \"base.toml\"\nseeds = [1, 2]\n"
                                       "[[study.group]]\nname = \"seed\"\nkey = \"specimen.seed\"\nvalues = [5, 6]\n";
  EXPECT_NE(error_of(dir).find("study.group[0].key: this group varies 'specimen.seed' itself"), std::string::npos)
      << error_of(dir);
  fs::remove_all(dir);
}

// A group varying packing.seed gets it into the run deck's specimen.seed (which wins in a run deck;
// the paper base deck has specimen.seed = 1, so varying packing.seed used to change nothing), and
// each run records the seed it uses.
TEST(Study, GroupVaryingTheSeedKeepsItsSeeds) {
  const fs::path dir = fs::temp_directory_path() / ("pbxmpm_study_seed_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  fs::copy_file(fs::path(PBXMPM_EXAMPLES_DIR) / "paper" / "base.toml", dir / "base.toml");
  std::ofstream(dir / "study.toml") << "[study]\nname = \"seeds\"\nbase = \"base.toml\"\n"
                                       "[[study.group]]\nname = \"seed\"\nkey = \"packing.seed\"\nvalues = [5, 6]\n";
  const StudySpec s = read_study((dir / "study.toml").string());
  ASSERT_EQ(s.runs.size(), 2u);
  EXPECT_EQ(s.runs[0].seed, 5);
  EXPECT_EQ(s.runs[1].id, "seed-6-s6");
  const toml::table deck = toml::parse(run_deck_text(s, s.runs[1]));
  EXPECT_EQ(deck["specimen"]["seed"].value<long>(), 6);
  EXPECT_EQ(deck["packing"]["seed"].value<long>(), 6);
  fs::remove_all(dir);
}

// A base deck whose specimen is read from a packing (specimen.packing_dir) gets no specimen.seed in
// its run decks (a run deck refuses the pair: a read packing has no seed), and several seeds are
// refused (they would all give the same run). Before, every such study stopped at its first run.
TEST(Study, SpecimenReadFromAPackingGetsNoSeed) {
  const fs::path dir = fs::temp_directory_path() / ("pbxmpm_study_packdir_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  std::string base = slurp(fs::path(PBXMPM_EXAMPLES_DIR) / "paper" / "base.toml");
  const auto a = base.find("[packing]"), b = base.find("\n[", a + 1);
  ASSERT_NE(a, std::string::npos);
  base.erase(a, b == std::string::npos ? std::string::npos : b + 1 - a);
  for (const char* sub : {"[packing.coarse]", "[packing.fine]"})
    if (const auto c = base.find(sub); c != std::string::npos) base.erase(c, base.find("\n[", c + 1) + 1 - c);
  const auto sp = base.find("[specimen]");
  ASSERT_NE(sp, std::string::npos);
  base.insert(base.find('\n', sp) + 1, "packing_dir = \"packing\"\n");
  const auto own_seed = base.find("seed = 1\n", sp);  // the paper base deck's own specimen.seed
  ASSERT_NE(own_seed, std::string::npos);
  base.erase(own_seed, 9);
  std::ofstream(dir / "base.toml") << base;
  std::ofstream(dir / "study.toml")
      << "[study]\nname = \"packdir\"\nbase = \"base.toml\"\n"
         "[[study.group]]\nname = \"t\"\nkey = \"run.temperature\"\nvalues = [\"293 K\"]\n";
  const StudySpec s = read_study((dir / "study.toml").string());
  const toml::table deck = toml::parse(run_deck_text(s, s.runs[0]));
  EXPECT_FALSE(deck["specimen"]["seed"]) << run_deck_text(s, s.runs[0]);
  EXPECT_EQ(deck["specimen"]["packing_dir"].value<std::string>(), "packing");
  std::ofstream(dir / "study.toml")
      << "[study]\nname = \"packdir\"\nbase = \"base.toml\"\nseeds = [1, 2]\n"
         "[[study.group]]\nname = \"t\"\nkey = \"run.temperature\"\nvalues = [\"293 K\"]\n";
  std::string msg = "(no error)";
  try {
    read_study((dir / "study.toml").string());
  } catch (const InputError& e) {
    msg = e.what();
  }
  EXPECT_NE(msg.find("study.seeds: the specimen is read from specimen.packing_dir"), std::string::npos) << msg;
  fs::remove_all(dir);
}

// A study-wide [analysis] table applies one linear window to every run, also to runs that were
// already finished when the study is resumed; its unknown keys are errors.
TEST(Study, AnalysisTableAppliesToEveryRunAndOnResume) {
  const fs::path dir = make_study();
  StudyOptions o;
  o.out_dir = (dir / "out").string();
  o.report = false;
  o.progress = false;
  {
    const StudySpec s = read_study((dir / "study.toml").string());
    EXPECT_FALSE(s.analysis.window_lo.has_value());
    ASSERT_EQ(run_study(s, o), 0);
    EXPECT_FALSE(fs::exists(dir / "out" / "analysis.toml"));  // no [analysis] table, no file
    EXPECT_NE(slurp(dir / "out" / "runs" / s.runs[0].id / "analysis.json").find("\"automatic\": true"),
              std::string::npos);
  }
  std::ofstream(dir / "study.toml", std::ios::app) << "\n[analysis]\nlinear_window = [0.002, 0.005]\n";
  const StudySpec s = read_study((dir / "study.toml").string());
  ASSERT_TRUE(s.analysis.window_lo.has_value());
  EXPECT_DOUBLE_EQ(*s.analysis.window_lo, 0.002);
  ASSERT_EQ(run_study(s, o), 0);  // both runs finished: skipped, but re-analysed with the window
  // the table is kept beside the runs for `pbxmpm report` / `fit study` (their default options)
  {
    ASSERT_TRUE(fs::exists(dir / "out" / "analysis.toml"));
    Deck kept = Deck::from_file((dir / "out" / "analysis.toml").string());
    const AnalysisOptions a = AnalysisOptions::from_deck(kept.root().table("analysis"));
    ASSERT_TRUE(a.window_lo.has_value());
    EXPECT_DOUBLE_EQ(*a.window_lo, 0.002);
    EXPECT_DOUBLE_EQ(*a.window_hi, 0.005);
  }
  for (const auto& r : s.runs) {
    const std::string a = slurp(dir / "out" / "runs" / r.id / "analysis.json");
    EXPECT_NE(a.find("\"automatic\": false"), std::string::npos) << r.id;
    EXPECT_NE(a.find("\"lo\": 0.002"), std::string::npos) << r.id;
  }
  std::ofstream(dir / "study.toml", std::ios::app) << "colour = 3\n";
  try {
    read_study((dir / "study.toml").string());
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("analysis.colour"), std::string::npos) << e.what();
  }
  fs::remove_all(dir);
}

// A study writes its [analysis] table into every run deck (after a marker line that the deck
// comparison leaves out, so runs made before keep being reused: the test above). A deck taken out
// of the study and run alone is then analysed by `pbxmpm analyze` as the study analysed it, from the
// copy of the deck in run.json; without the table the automatic window's defaults applied silently
// (a 5 um run of the quick deck read E 6.3 GPa at a knee in the start's ringing instead of 1.6). A
// misspelt key of the table stops the run before it starts.
TEST(Study, RunDeckTakenOutOfTheStudyIsAnalysedByItsTable) {
  const fs::path dir = make_study("", "[10]");
  std::ofstream(dir / "study.toml", std::ios::app) << "\n[analysis]\nlinear_window = [0.002, 0.005]\n";
  const StudySpec s = read_study((dir / "study.toml").string());
  const std::string text = run_deck_text(s, s.runs[0]);
  const toml::table deck = toml::parse(text);
  ASSERT_TRUE(deck["analysis"]["linear_window"].is_array()) << text;
  EXPECT_DOUBLE_EQ(deck["analysis"]["linear_window"][0].value_or(0.0), 0.002);
  std::ofstream(dir / "alone.toml") << text;
  const std::string bin = PBXMPM_BINARY;
  const std::string run = bin + " run " + (dir / "alone.toml").string() + " --out " + (dir / "alone").string() +
                          " -q --threads 1 > " + (dir / "run.log").string() + " 2>&1";
  ASSERT_EQ(std::system(run.c_str()), 0) << slurp(dir / "run.log");
  const std::string analyze =
      bin + " analyze " + (dir / "alone").string() + " > " + (dir / "an.log").string() + " 2>&1";
  ASSERT_EQ(std::system(analyze.c_str()), 0) << slurp(dir / "an.log");
  EXPECT_NE(slurp(dir / "an.log").find("the run deck's [analysis] table"), std::string::npos) << slurp(dir / "an.log");
  const std::string a = slurp(dir / "alone" / "analysis.json");
  EXPECT_NE(a.find("\"automatic\": false"), std::string::npos) << a;
  EXPECT_NE(a.find("\"lo\": 0.002"), std::string::npos) << a;
  // --options still wins over the deck's table
  std::ofstream(dir / "opts.toml") << "[analysis]\nlinear_window = [0.001, 0.004]\n";
  const std::string again = bin + " analyze " + (dir / "alone").string() + " --options " +
                            (dir / "opts.toml").string() + " > " + (dir / "an2.log").string() + " 2>&1";
  ASSERT_EQ(std::system(again.c_str()), 0) << slurp(dir / "an2.log");
  EXPECT_NE(slurp(dir / "alone" / "analysis.json").find("\"lo\": 0.001"), std::string::npos);
  // a misspelt key in a run deck's table is an error naming it, before any step
  std::string bad = text;
  bad += "window_min_pointz = 20\n";
  const Deck d = Deck::from_string(bad, "bad.toml");
  try {
    build_scene<2>(d);
    d.check_unused();  // as every command does before the first step
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("analysis.window_min_pointz"), std::string::npos) << e.what();
  }
  // and a value out of range is refused by the scene's reader itself
  std::string out_of_range = text;
  out_of_range += "window_min_points = 2\n";
  EXPECT_THROW(build_scene<2>(Deck::from_string(out_of_range, "range.toml")), InputError);
  fs::remove_all(dir);
}

// A finished run whose analysis.json is missing (the analysis failed, or was deleted) is
// re-analysed when the study is started again, not simulated again: its history.csv stays the
// same file (it used to be rewritten by a whole new run). Names with quotes and a tab give valid
// JSON (the hand-written writers escaped quotes but not control characters).
TEST(Study, FinishedRunWithoutAnalysisIsReanalysedNotRerun) {
  const fs::path dir = make_study();
  std::string text = slurp(dir / "study.toml");
  text.replace(text.find("name = \"mpi-check\""), 18, "name = \"a \\\"quoted\\\"\\tstudy\"");
  std::ofstream(dir / "study.toml") << text;
  StudyOptions o;
  o.out_dir = (dir / "out").string();
  o.report = false;
  o.progress = false;
  const StudySpec s = read_study((dir / "study.toml").string());
  EXPECT_EQ(s.name, "a \"quoted\"\tstudy");
  ASSERT_EQ(run_study(s, o), 0);
  const fs::path run = dir / "out" / "runs" / s.runs[0].id;
  const std::string history = slurp(run / "history.csv");
  const std::string run_json = slurp(run / "run.json");
  fs::remove(run / "analysis.json");
  ASSERT_EQ(run_study(s, o), 0);
  EXPECT_TRUE(fs::exists(run / "analysis.json"));
  EXPECT_EQ(slurp(run / "run.json"), run_json) << "the run was simulated again";
  EXPECT_EQ(slurp(run / "history.csv"), history);
  // study.json and the runs' study block parse and give the name back (it is escaped)
  EXPECT_EQ(json_string(*json_find(json_parse(slurp(dir / "out" / "study.json")), "name")), s.name);
  EXPECT_EQ(json_string(*json_find(*json_find(json_parse(run_json), "study"), "study")), s.name);
  fs::remove_all(dir);
}

// An invalid run deck anywhere in the study stops it before the first run starts.
TEST(Study, InvalidRunDeckStopsTheStudyBeforeAnyRun) {
  const fs::path dir = make_study("", "[10, -20]");
  StudyOptions o;
  o.out_dir = (dir / "out").string();
  o.report = false;
  o.progress = false;
  const StudySpec s = read_study((dir / "study.toml").string());
  ASSERT_EQ(s.runs.size(), 2u);
  EXPECT_EQ(run_study(s, o), kStudyNotStarted);
  for (const auto& r : s.runs) EXPECT_FALSE(fs::exists(dir / "out" / "runs" / r.id / "history.csv")) << r.id;
  fs::remove_all(dir);
}

// The runs still to do are dealt to the ranks in study order, so a resumed study keeps every rank
// busy (dealing all runs by index would leave rank 1 idle when runs 1 and 3 had finished).
TEST(Study, PendingRunsAreDealtRoundRobin) {
  const std::vector<bool> pending = {true, false, true, true, false, true};
  EXPECT_EQ(runs_of_rank(pending, 2, 0), (std::vector<std::size_t>{0, 3}));
  EXPECT_EQ(runs_of_rank(pending, 2, 1), (std::vector<std::size_t>{2, 5}));
  EXPECT_EQ(runs_of_rank(pending, 1, 0), (std::vector<std::size_t>{0, 2, 3, 5}));
  EXPECT_EQ(runs_of_rank(pending, 5, 4), (std::vector<std::size_t>{}));
}

// --only runs the named runs alone; the report waits for the others; an unknown id is an error
// naming it and the study's runs.
TEST(Study, OnlyRunsTheNamedRunsAndTheReportWaits) {
  const fs::path dir = make_study();
  const StudySpec s = read_study((dir / "study.toml").string());
  ASSERT_EQ(s.runs.size(), 2u);
  StudyOptions o;
  o.out_dir = (dir / "out").string();
  o.progress = false;
  o.only = {s.runs[1].id};
  EXPECT_EQ(run_study(s, o), 0);
  EXPECT_TRUE(fs::exists(dir / "out" / "runs" / s.runs[1].id / "analysis.json"));
  EXPECT_FALSE(fs::exists(dir / "out" / "runs" / s.runs[0].id));
  EXPECT_FALSE(fs::exists(dir / "out" / "report"));
  o.only = {"scaling-nothing-s1"};
  try {
    run_study(s, o);
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("'scaling-nothing-s1'"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find(s.runs[0].id), std::string::npos) << e.what();
  }
  fs::remove_all(dir);
}

// A resumed study under mpirun shares the runs left between the ranks: with the middle one of
// three finished, rank 0 takes the first and rank 1 the last (dealing all runs by index would give
// rank 1 only the finished one and leave it idle). Also: --only under mpirun, and its unknown id.
TEST(Study, ResumedStudyUnderMpiKeepsBothRanksBusy) {
  const fs::path dir = make_study("", "[10, 20, 30]");
  const StudySpec s = read_study((dir / "study.toml").string());
  ASSERT_EQ(s.runs.size(), 3u);
  StudyOptions o;
  o.out_dir = (dir / "out").string();
  o.report = false;
  o.progress = false;
  o.only = {s.runs[1].id};
  ASSERT_EQ(run_study(s, o), 0);
#ifndef PBXMPM_HAVE_MPI
  GTEST_SKIP() << "built without MPI (-DPBXMPM_WITH_MPI=OFF)";
#endif
  if (std::system("command -v mpirun > /dev/null 2>&1") != 0) GTEST_SKIP() << "mpirun not installed";
  const std::string mpi = "OMP_NUM_THREADS=1 mpirun --allow-run-as-root --oversubscribe -n 2 " +
                          std::string(PBXMPM_BINARY) + " study " + (dir / "study.toml").string() + " --out " +
                          (dir / "out").string() + " --quiet --no-report";
  ASSERT_NE(std::system((mpi + " --only scaling-99-s1 > " + (dir / "bad.log").string() + " 2>&1").c_str()), 0);
  EXPECT_NE(slurp(dir / "bad.log").find("'scaling-99-s1'"), std::string::npos) << slurp(dir / "bad.log");
  ASSERT_EQ(std::system((mpi + " > " + (dir / "mpi.log").string() + " 2>&1").c_str()), 0) << slurp(dir / "mpi.log");
  const std::string log = slurp(dir / "mpi.log");
  EXPECT_NE(log.find("[1/1] " + s.runs[0].id + " (rank 0"), std::string::npos) << log;
  EXPECT_NE(log.find("[1/1] " + s.runs[2].id + " (rank 1"), std::string::npos) << log;
  EXPECT_NE(log.find(s.runs[1].id + " already finished"), std::string::npos) << log;
  for (const auto& r : s.runs) EXPECT_TRUE(fs::exists(dir / "out" / "runs" / r.id / "analysis.json")) << r.id;
  if (!HasFailure()) fs::remove_all(dir);
}

// A run stopped mid-way (here: by an exception after 23 history rows, with a checkpoint every 5)
// continues from its checkpoint when the study is started again, and ends with the same
// history.csv, to the last digit, as the run made in one go; run.json counts the restart and the
// checkpoint is removed once the run has finished. A checkpoint made from another deck stops the
// study before any run starts.
TEST(Study, InterruptedRunContinuesFromItsCheckpoint) {
  const fs::path dir = make_study();
  const StudySpec s = read_study((dir / "study.toml").string());
  ASSERT_EQ(s.runs.size(), 2u);
  const auto& r = s.runs[0];
  StudyOptions o;
  o.report = false;
  o.progress = false;
  o.only = {r.id};
  o.out_dir = (dir / "whole").string();
  o.checkpoint_every = 0;
  ASSERT_EQ(run_study(s, o), 0);
  const std::string whole = slurp(dir / "whole" / "runs" / r.id / "history.csv");

  const fs::path cut = dir / "cut" / "runs" / r.id;
  interrupt_run(s, r, cut, 23);
  ASSERT_TRUE(fs::exists(cut / "checkpoint.h5"));
  ASSERT_NE(slurp(cut / "history.csv"), whole);
  // the other run gets a checkpoint of this run's deck: refused, nothing runs
  fs::create_directories(dir / "cut" / "runs" / s.runs[1].id);
  fs::copy_file(cut / "checkpoint.h5", dir / "cut" / "runs" / s.runs[1].id / "checkpoint.h5");
  o.out_dir = (dir / "cut").string();
  o.only = {};
  o.checkpoint_every = 10;
  EXPECT_EQ(run_study(s, o), kStudyNotStarted);
  EXPECT_FALSE(fs::exists(dir / "cut" / "runs" / s.runs[1].id / "history.csv"));
  EXPECT_NE(slurp(cut / "history.csv"), whole);
  fs::remove(dir / "cut" / "runs" / s.runs[1].id / "checkpoint.h5");
  // the study continues the interrupted run
  o.only = {r.id};
  ASSERT_EQ(run_study(s, o), 0);
  EXPECT_EQ(slurp(cut / "history.csv"), whole);
  EXPECT_FALSE(fs::exists(cut / "checkpoint.h5"));
  const std::string run_json = slurp(cut / "run.json");
  EXPECT_NE(run_json.find("\"restarts\": 1,"), std::string::npos) << run_json;
  EXPECT_NE(run_json.find("\"status\": \"finished\""), std::string::npos) << run_json;
  EXPECT_NE(run_json.find("; 0."), std::string::npos) << "two segments' code versions: " << run_json;

  // a checkpoint that cannot be continued (its history.csv lost rows) is set aside and the run
  // starts over, ending with the same history
  const fs::path cut2 = dir / "cut2" / "runs" / r.id;
  interrupt_run(s, r, cut2, 12);
  {
    std::istringstream in(slurp(cut2 / "history.csv"));
    std::string line, head;
    for (int i = 0; i < 4 && std::getline(in, line); ++i) head += line + "\n";
    std::ofstream(cut2 / "history.csv") << head;  // header and 3 rows; the checkpoint had 10
  }
  o.out_dir = (dir / "cut2").string();
  ASSERT_EQ(run_study(s, o), 0);
  EXPECT_EQ(slurp(cut2 / "history.csv"), whole);
  EXPECT_TRUE(fs::exists(cut2 / "checkpoint.unusable.h5"));
  EXPECT_NE(slurp(cut2 / "run.json").find("\"restarts\": 0,"), std::string::npos);
  if (!HasFailure()) fs::remove_all(dir);
}

// Without a terminal, the progress lines of a study's runs name the run and the study's ETA, and
// the line that starts a run says how many of the study's runs have finished.
TEST(Study, ProgressLinesNameTheRunAndTheStudyEta) {
  const fs::path dir = make_study();
  const std::string cmd = "OMP_NUM_THREADS=1 " + std::string(PBXMPM_BINARY) + " study " +
                          (dir / "study.toml").string() + " --out " + (dir / "out").string() + " --no-report > " +
                          (dir / "log").string() + " 2>&1";
  ASSERT_EQ(std::system(cmd.c_str()), 0) << slurp(dir / "log");
  const std::string log = slurp(dir / "log");
  EXPECT_NE(log.find("(run 1/2, 2 runs in the study, study ETA "), std::string::npos) << log;
  EXPECT_NE(log.find("(run 2/2, 2 runs in the study, study ETA "), std::string::npos) << log;
  // The line starting each run counts the study's finished runs, read from the folder.
  EXPECT_NE(log.find("(rank 0, 0/2 runs of the study finished, "), std::string::npos) << log;
  EXPECT_NE(log.find("(rank 0, 1/2 runs of the study finished, "), std::string::npos) << log;
  if (!HasFailure()) fs::remove_all(dir);
}

// The study ETA in the progress lines: this run's remaining time plus the runs still to come at
// this run's projected length; a restarted run projects from the part made since the restart.
TEST(Study, EtaCountsTheRunsStillToComeAtThisRunsPace) {
  EXPECT_DOUBLE_EQ(study_eta_s(100, 0.25, 0, 0), 300);          // 400 s per run, 3/4 to go
  EXPECT_DOUBLE_EQ(study_eta_s(100, 0.25, 0, 2), 300 + 800);    // and two more runs
  EXPECT_DOUBLE_EQ(study_eta_s(100, 0.75, 0.5, 1), 100 + 400);  // restarted at 50 %: 400 s per run
  EXPECT_LT(study_eta_s(0, 0, 0, 3), 0);                        // nothing measured yet: unknown
  EXPECT_LT(study_eta_s(10, 0.5, 0.5, 3), 0);
}

// `pbxmpm status`: a finished run, an interrupted one (strain reached, checkpoint step) and one not
// started, read from the files alone; the last line names the runs still to do.
TEST(Study, StatusSaysWhereEachRunStands) {
  const fs::path dir = make_study("", "[10, 20, 30]");
  const StudySpec s = read_study((dir / "study.toml").string());
  StudyOptions o;
  o.out_dir = (dir / "out").string();
  o.report = false;
  o.progress = false;
  o.only = {s.runs[0].id};
  ASSERT_EQ(run_study(s, o), 0);
  interrupt_run(s, s.runs[1], dir / "out" / "runs" / s.runs[1].id, 12);
  const auto st = study_status((dir / "out").string());
  ASSERT_EQ(st.size(), 3u);
  EXPECT_EQ(st[0].state, "finished");
  EXPECT_NEAR(st[0].strain, st[0].end_strain, 1e-4);  // the run reached its end strain
  EXPECT_EQ(st[1].state, "failed");                   // the exception marked it so
  EXPECT_GT(st[1].strain, 0);
  EXPECT_LT(st[1].strain, 0.5 * st[0].strain);
  EXPECT_GT(st[1].checkpoint_step, 0);
  EXPECT_EQ(st[2].state, "not started");
  EXPECT_LT(st[2].strain, 0);
  const std::string table = format_study_status(st, (dir / "out").string());
  EXPECT_NE(table.find("1 of 3 runs finished"), std::string::npos) << table;
  EXPECT_NE(table.find("--only " + s.runs[1].id + "," + s.runs[2].id), std::string::npos) << table;
  // the command to continue names the study deck itself (study.json records it), not a placeholder
  EXPECT_NE(table.find("pbxmpm study " + fs::absolute(dir / "study.toml").string() + " --out"), std::string::npos)
      << table;
  EXPECT_THROW(study_status((dir / "nothing").string()), InputError);
  // a run.json still "running": alive if its process (here: this test) is, interrupted if not
  const fs::path rj = dir / "out" / "runs" / s.runs[1].id / "run.json";
  std::string json = slurp(rj);
  const std::string pid = fmt::format("\"pid\": {},", ::getpid());
  ASSERT_NE(json.find(pid), std::string::npos) << json;
  json.replace(json.find("\"status\": \"failed\""), 18, "\"status\": \"running\"");
  std::ofstream(rj) << json;
  EXPECT_EQ(study_status((dir / "out").string())[1].state, "running");
  json.replace(json.find(pid), pid.size(), "\"pid\": 999999999,");  // above any pid_max
  std::ofstream(rj) << json;
  EXPECT_EQ(study_status((dir / "out").string())[1].state, "interrupted");
  if (!HasFailure()) fs::remove_all(dir);
}

// Under mpirun, a study folder rank 0 cannot create (its parent is a file) ends the job with a
// message on every rank's exit code; the other rank used to wait for rank 0 for ever (the test's
// 5-minute timeout would catch that hang).
TEST(Study, StudyFolderThatCannotBeMadeEndsEveryRank) {
#ifndef PBXMPM_HAVE_MPI
  GTEST_SKIP() << "built without MPI (-DPBXMPM_WITH_MPI=OFF)";
#endif
  if (std::system("command -v mpirun > /dev/null 2>&1") != 0) GTEST_SKIP() << "mpirun not installed";
  const fs::path dir = make_study();
  std::ofstream(dir / "a_file") << "not a folder\n";
  const std::string cmd = "OMP_NUM_THREADS=1 timeout 120 mpirun --allow-run-as-root --oversubscribe -n 2 " +
                          std::string(PBXMPM_BINARY) + " study " + (dir / "study.toml").string() + " --out " +
                          (dir / "a_file" / "out").string() + " --quiet --no-report > " + (dir / "mpi.log").string() +
                          " 2>&1";
  const int status = std::system(cmd.c_str());
  ASSERT_TRUE(WIFEXITED(status)) << slurp(dir / "mpi.log");
  EXPECT_NE(WEXITSTATUS(status), 0) << slurp(dir / "mpi.log");
  EXPECT_NE(WEXITSTATUS(status), 124) << "the ranks hung (timeout):\n" << slurp(dir / "mpi.log");
  EXPECT_NE(slurp(dir / "mpi.log").find("the study did not start"), std::string::npos) << slurp(dir / "mpi.log");
  fs::remove_all(dir);
}

// A relative specimen.packing_dir in the base deck is found beside the base deck, wherever the
// study is started from (it was looked up in the current folder by the deck check and in the
// run's folder by the run, so such a study could not run from anywhere).
TEST(Study, RelativePackingDirResolvesBesideTheBaseDeck) {
  const fs::path dir = fs::temp_directory_path() / ("pbxmpm_study_relpack_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir / "decks");
  std::string base = slurp(fs::path(PBXMPM_EXAMPLES_DIR) / "paper" / "base.toml");
  // the specimen from a packing of four coated grains in the paper's 1.0 x 1.2 mm box
  const auto a = base.find("[packing]");
  ASSERT_NE(a, std::string::npos);
  const auto b = base.find("[materials.");
  base.erase(a, b - a);
  const auto sp = base.find("[specimen]");
  base.insert(base.find('\n', sp) + 1, "packing_dir = \"packing\"\n");
  base.erase(base.find("seed = 1\n", sp), 9);
  std::ofstream(dir / "decks" / "base.toml") << base;
  Packing p;
  p.box = {1.0e-3, 1.2e-3};
  p.periodic = false;
  p.tatb_density = 1934;
  p.binder_density = 2020;
  p.contact_gap = 2e-6;
  for (int i = 0; i < 4; ++i) {
    Grain g;
    g.centre = {0.25e-3 + 0.5e-3 * (i % 2), 0.3e-3 + 0.6e-3 * (i / 2)};
    g.diameter = 0.3e-3;
    g.coat = 4e-6;
    g.colour = i;
    p.grains.push_back(g);
  }
  write_packing(p, (dir / "decks" / "packing").string());
  std::ofstream(dir / "study.toml")
      << "[study]\nname = \"relpack\"\nbase = \"decks/base.toml\"\n"
         "[study.set]\n\"grid.cell_size\" = \"20 um\"\n\"run.end_strain\" = 0.01\n"
         "\"run.history_points\" = 100\n\"run.snapshots\" = 0\n"
         "[[study.group]]\nname = \"t\"\nkey = \"run.temperature\"\nvalues = [\"293 K\"]\n"
         "[analysis]\nlinear_window = [0.0042, 0.0095]\nstrength_max_strain = 0.01\n";
  const StudySpec s = read_study((dir / "study.toml").string());
  StudyOptions o;
  o.out_dir = (dir / "out").string();
  o.report = false;
  o.progress = false;
  ASSERT_EQ(run_study(s, o), 0);  // started from the test's folder, not the base deck's
  EXPECT_NE(slurp(dir / "out" / "runs" / s.runs[0].id / "run.json").find("\"status\": \"finished\""),
            std::string::npos);
  fs::remove_all(dir);
}

// A group that gives the seed itself on a specimen no seed reaches (read from a packing, or no
// specimen at all) would make several names for one run; a seed that is not a whole number would
// be cut (2.5 became 2 while study.json said 2.5). Both are refused naming the key.
TEST(Study, SeedsThatWouldNotReachTheRunAreRefused) {
  const fs::path dir = make_study();  // the demo deck: no [specimen]
  std::ofstream(dir / "study.toml") << "[study]\nname = \"seeds\"\nbase = \"base.toml\"\n"
                                       "[[study.group]]\nname = \"seed\"\nkey = \"specimen.seed\"\nvalues = [5, 6]\n";
  EXPECT_NE(error_of(dir).find(
                "study.group[0].key: group 'seed' gives the specimen's seed, but the base deck has no [specimen]"),
            std::string::npos)
      << error_of(dir);
  fs::copy_file(fs::path(PBXMPM_EXAMPLES_DIR) / "paper" / "base.toml", dir / "base.toml",
                fs::copy_options::overwrite_existing);
  std::ofstream(dir / "study.toml")
      << "[study]\nname = \"seeds\"\nbase = \"base.toml\"\n"
         "[[study.group]]\nname = \"seed\"\nkey = \"packing.seed\"\nvalues = [1.5, 2.5]\n";
  EXPECT_NE(error_of(dir).find("study.group[0].values: seed '1.5' is not a non-negative integer"), std::string::npos)
      << error_of(dir);
  std::ofstream(dir / "study.toml") << "[study]\nname = \"seeds\"\nbase = \"base.toml\"\n"
                                       "[[study.group]]\nname = \"../seed\"\nkey = \"packing.seed\"\nvalues = [1, 2]\n";
  EXPECT_NE(error_of(dir).find("study.group[0].name: '../seed' names a folder"), std::string::npos) << error_of(dir);
  fs::remove_all(dir);
}

// An unreadable checkpoint (here: empty) is set aside and its run starts over, as the docs say;
// it used to stop the whole study before any run.
TEST(Study, UnreadableCheckpointIsSetAsideAndTheRunStartsOver) {
  const fs::path dir = make_study("", "[10]");
  const StudySpec s = read_study((dir / "study.toml").string());
  const fs::path run = dir / "out" / "runs" / s.runs[0].id;
  fs::create_directories(run);
  std::ofstream(run / "checkpoint.h5") << "";
  StudyOptions o;
  o.out_dir = (dir / "out").string();
  o.report = false;
  o.progress = false;
  ASSERT_EQ(run_study(s, o), 0);
  EXPECT_NE(slurp(run / "run.json").find("\"status\": \"finished\""), std::string::npos);
  EXPECT_TRUE(fs::exists(run / "checkpoint.unusable.h5"));
  fs::remove_all(dir);
}

// A run that fails on one rank of an MPI study (here its analysis: a run to 49 % strain sampled every
// 1 % leaves too few rows in the moduli window): the rank names the run and the reason, the other
// rank's run finishes with its analysis, the study exits non-zero without a report, and the same
// command again re-analyses the failed run without running it, and leaves the finished one alone.
TEST(Study, RunFailingOnOneRankLeavesTheOtherRanksRunsWhole) {
#ifndef PBXMPM_HAVE_MPI
  GTEST_SKIP() << "built without MPI (-DPBXMPM_WITH_MPI=OFF)";
#endif
  if (std::system("command -v mpirun > /dev/null 2>&1") != 0) GTEST_SKIP() << "mpirun not installed";
  const fs::path dir = make_study();
  std::ofstream(dir / "study.toml") << "[study]\nname = \"rank-fails\"\nbase = \"base.toml\"\n"
                                       "[study.set]\n\"solver.mass_scaling\" = 10000\n"
                                       "[[study.group]]\nname = \"strain\"\nkey = \"run.end_strain\"\n"
                                       "values = [0.006, 0.49]\n";
  const std::string cmd = "OMP_NUM_THREADS=1 timeout 120 mpirun --allow-run-as-root --oversubscribe -n 2 " +
                          std::string(PBXMPM_BINARY) + " study " + (dir / "study.toml").string() + " --out " +
                          (dir / "out").string() + " --quiet > " + (dir / "mpi.log").string() + " 2>&1";
  const StudySpec s = read_study((dir / "study.toml").string());
  ASSERT_EQ(s.runs.size(), 2u);
  const fs::path good = dir / "out" / "runs" / s.runs[0].id, bad = dir / "out" / "runs" / s.runs[1].id;
  int status = std::system(cmd.c_str());
  const std::string log = slurp(dir / "mpi.log");
  ASSERT_TRUE(WIFEXITED(status)) << log;
  EXPECT_NE(WEXITSTATUS(status), 0) << log;
  EXPECT_NE(WEXITSTATUS(status), 124) << "the ranks hung (timeout):\n" << log;
  const std::string said = "run " + s.runs[1].id + " finished, but its analysis failed: linear window";
  EXPECT_NE(log.find(said), std::string::npos) << log;
  EXPECT_NE(log.find("1 run of the study failed"), std::string::npos) << log;
  EXPECT_NE(slurp(good / "run.json").find("\"status\": \"finished\""), std::string::npos);
  EXPECT_TRUE(fs::exists(good / "analysis.json"));
  EXPECT_NE(slurp(bad / "run.json").find("\"status\": \"finished\""), std::string::npos);
  EXPECT_FALSE(fs::exists(bad / "analysis.json"));
  EXPECT_FALSE(fs::exists(dir / "out" / "report")) << "a report from a study with a failed run";
  // the same command again: neither run is made again; the failed analysis is tried again
  const auto stamp_good = fs::last_write_time(good / "history.csv"),
             stamp_bad = fs::last_write_time(bad / "history.csv");
  status = std::system(cmd.c_str());
  EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) != 0 && WEXITSTATUS(status) != 124) << slurp(dir / "mpi.log");
  EXPECT_EQ(fs::last_write_time(good / "history.csv"), stamp_good);
  EXPECT_EQ(fs::last_write_time(bad / "history.csv"), stamp_bad);
  EXPECT_NE(slurp(dir / "mpi.log").find("linear window"), std::string::npos) << slurp(dir / "mpi.log");
  fs::remove_all(dir);
}
