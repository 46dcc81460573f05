// The command line refuses bad input with a message naming the option, column or key, and a
// non-zero exit code: nothing is ignored, clamped or read in a unit it does not state. Each case
// runs the pbxmpm binary on a small input (well under a second).
#include <algorithm>
#include <array>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <sstream>
#include <string>
#include <vector>

#include <sys/wait.h>
#include <unistd.h>

#include <fmt/format.h>
#include <gtest/gtest.h>

#include "../engine/block_deck.hpp"
#include "binary_test.hpp"
#include "io/output_lock.hpp"

namespace fs = std::filesystem;

namespace {

using pbx::test::pbxmpm;
using pbx::test::Result;

class CommandLine : public pbx::test::BinaryTest {
 protected:
  CommandLine() : BinaryTest("pbx_test_cli_") {}
  // expects a failure (exit code != 0) whose output contains `what`
  void expect_refused(const std::string& args, const std::string& what) const {
    const Result r = pbxmpm(args);
    EXPECT_NE(r.code, 0) << args << "\n" << r.output;
    EXPECT_NE(r.output.find(what), std::string::npos) << args << "\nexpected '" << what << "' in:\n" << r.output;
  }
};

}  // namespace

// fit reads users' files: an unreadable cell is an error at its line (it used to drop the row), a
// stress, density or temperature column must state its unit in its name, and the options are
// range-checked.
TEST_F(CommandLine, FitRefusesUnreadableCellsUnstatedUnitsAndBadOptions) {
  const std::string good =
      write("t.csv", "T_K,strength_MPa,strength\n293,32.8,32.8e6\n333,28.2,28.2e6\n353,24.1,24.1e6\n373,15.6,15.6e6\n");
  EXPECT_EQ(pbxmpm("fit temperature " + good).code, 0);
  const std::string cell = write("cell.csv", "T_K,strength_MPa\n293,32.8\n333,28.2 MPa\n353,24.1\n373,15.6\n");
  expect_refused("fit temperature " + cell, "cell.csv:3: column 'strength_MPa' holds '28.2 MPa', not a finite number");
  const std::string nan = write("nan.csv", "T_K,strength_MPa\n293,32.8\n333,nan\n353,24.1\n373,15.6\n");
  expect_refused("fit temperature " + nan, "nan.csv:3: column 'strength_MPa' holds 'nan'");
  expect_refused("fit temperature " + good + " --strength-col strength",
                 "--strength-col 'strength': the column name must end with its unit");
  const std::string celsius = write("c.csv", "T_C,strength_MPa\n20,32.8\n60,28.2\n80,24.1\n100,15.6\n");
  expect_refused("fit temperature " + celsius + " --T-col T_C",
                 "--T-col 'T_C': the column name must end with its unit, _K");
  expect_refused("fit temperature " + good + " --confidence 1.5", "--confidence: must lie in (0, 1)");
  const std::string dens =
      write("d.csv", "density_g_cm3,G_GPa,K_GPa\n1.761,1.03,2.21\n1.787,1.24,2.65\n1.839,1.72,3.68\n");
  EXPECT_EQ(pbxmpm("fit density " + dens).code, 0);
  expect_refused("fit density " + dens + " --rho0 '-1 kg/m3'", "--rho0: must be a finite quantity > 0");
  const std::string curve = write("curve.csv", "strain,punch_stress_Pa\n0.01,1e6\n0.02,2e6\n0.03,2.5e6\n");
  expect_refused("fit curve " + curve + " --window 5:9", "no row has 'strain' in the window 5 .. 9 % strain");
  expect_refused("fit curve " + curve + " --window 3:0.5", "--window: needs 0 <= LO < HI");
  expect_refused("fit curve " + curve + " --window 0.5:3:4", "--window: expected two finite numbers LO:HI");
}

// A value that overflows in SI units (1e303 MPa) is refused naming the column and row (the fit gave
// NaN parameters with R^2 = 1, "converged"); a fit with as many points as parameters says it has
// no confidence interval instead of printing NaN intervals without a word.
TEST_F(CommandLine, FitRefusesOverflowAndSaysWhenItHasNoDegreesOfFreedom) {
  const std::string big = write("big.csv", "T_K,strength_MPa\n293,1e303\n333,28.2\n353,24.1\n373,15.6\n");
  expect_refused("fit temperature " + big,
                 "column 'strength_MPa', data row 1: 1e+303 overflows when converted to SI units");
  const std::string two = write("two.csv", "T_K,strength_MPa\n293,32.8\n373,15.6\n");
  const Result r = pbxmpm("fit temperature " + two);
  EXPECT_EQ(r.code, 0) << r.output;
  EXPECT_NE(r.output.find("no degrees of freedom (2 points for 2 parameters)"), std::string::npos) << r.output;
  EXPECT_EQ(r.output.find("nan"), std::string::npos) << r.output;
}

// The messages a hostile user found unclear (issue 24), each now naming its cause.
TEST_F(CommandLine, ErrorsNameTheirCause) {
  std::ifstream in(fs::path(PBXMPM_EXAMPLES_DIR) / "demo" / "elastic_block_die.toml");
  const std::string demo((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  auto variant = [&](const std::string& name, const std::string& from, const std::string& to) {
    std::string t = demo;
    const auto at = t.find(from);
    EXPECT_NE(at, std::string::npos) << from;
    if (at != std::string::npos) t.replace(at, from.size(), to);
    return write(name, t);
  };
  const std::string both = variant("both.toml", "shear_modulus = \"11.5 GPa\"",
                                   "shear_modulus = \"11.5 GPa\"\nyoungs_modulus = \"20 GPa\"\npoisson_ratio = 0.2");
  expect_refused("check " + both,
                 "give bulk_modulus and shear_modulus, or youngs_modulus and poisson_ratio, not both pairs");
  expect_refused("check " + variant("big.toml", "cell_size = \"20 um\"", "cell_size = \"1e999 um\""),
                 "grid.cell_size: the number in '1e999 um' is beyond the range of a double");
  expect_refused("check " + variant("rho.toml", "density = \"1.934 g/cm3\"", "density = 1e308"),
                 "materials.block.density: 1e+308 kg/m3 exceeds 1e5 kg/m3");
  expect_refused("check " + variant("ms.toml", "mass_scaling = 10", "mass_scaling = 1e9"),
                 "solver.mass_scaling: must be <= 10000");
  expect_refused("rnu " + both, "unknown command 'rnu' (the commands: run, check");
  expect_refused("fit tempreature x.csv",
                 "pbxmpm fit: unknown command 'tempreature' (the commands: temperature, curve");
  EXPECT_EQ(pbxmpm("run --threads 0 " + both).code, 2) << "a usage error exits 2, not CLI11's 105";
  expect_refused("analyze " + both, "is a file: give the run's folder");
  expect_refused(
      "material " + both + " --material block --path uniaxial_strain --strain -0.01 --rate 100 --steps 100000000000",
      "--steps");
  const pbx::test::Result omp = pbx::test::shell(fmt::format(
      "OMP_NUM_THREADS=abc {{pbx}} run {} -q --out {}",
      (fs::path(PBXMPM_EXAMPLES_DIR) / "demo" / "elastic_block_die.toml").string(), (dir / "omp").string()));
  EXPECT_EQ(omp.code, 2) << omp.output;
  EXPECT_NE(omp.output.find("OMP_NUM_THREADS='abc' is not a thread count"), std::string::npos) << omp.output;
  // a plain number is SI, as in the decks
  const std::string two = write("two.csv", "T_K,strength_MPa\n293,32.8\n333,28.2\n373,15.6\n");
  EXPECT_EQ(pbxmpm("fit temperature " + two + " --T0 293").code, 0);
  // a study whose base is a folder or a study deck is refused before anything is written
  const std::string s1 = write("s1.toml",
                               "[study]\nname = \"x\"\nbase = \".\"\n[[study.group]]\nname = \"a\"\n"
                               "key = \"solver.mass_scaling\"\nvalues = [10]\n");
  expect_refused("study " + s1 + " --out " + (dir / "s1").string(), "' is a folder, not a run deck");
  EXPECT_FALSE(fs::exists(dir / "s1"));
  const std::string s2 = write("s2.toml",
                               "[study]\nname = \"x\"\nbase = \"s2.toml\"\n[[study.group]]\nname = \"a\"\n"
                               "key = \"solver.mass_scaling\"\nvalues = [10]\n");
  expect_refused("study " + s2 + " --out " + (dir / "s2").string(), "study.base: names this study deck itself");
}

// --set overrides a key of the deck before it is read, so the override is checked like the deck
// (an unknown key, a value that is not TOML, a key a study group varies are refused) and the run
// records it; one closing line says where the results are.
TEST_F(CommandLine, SetOverridesADeckKeyCheckedLikeTheDeck) {
  const std::string demo = (fs::path(PBXMPM_EXAMPLES_DIR) / "demo" / "elastic_block_die.toml").string();
  const fs::path out = dir / "set";
  const Result r = pbxmpm(
      fmt::format("run {} --set run.end_strain=0.004 --set solver.mass_scaling=100 --out {} -q", demo, out.string()));
  ASSERT_EQ(r.code, 0) << r.output;
  EXPECT_NE(r.output.find("pbxmpm: finished: "), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("results in " + out.string()), std::string::npos) << r.output;
  std::ifstream h(out / "history.csv");
  std::string line, last;
  while (std::getline(h, line)) last = line;
  std::vector<std::string> cells;
  for (std::size_t a = 0, b = 0; b != std::string::npos; a = b + 1) {
    b = last.find(',', a);
    cells.push_back(last.substr(a, b == std::string::npos ? std::string::npos : b - a));
  }
  ASSERT_GT(cells.size(), 3u);
  EXPECT_EQ(cells[3], "0.004") << "the strain of the last row: " << last;
  expect_refused(fmt::format("check {} --set 'grid.cel_size=\"10 um\"'", demo),
                 "(as rewritten by --set):9: unknown key 'grid.cel_size'");
  expect_refused(fmt::format("check {} --set 'grid.cell_size=10 um'", demo),
                 "--set 'grid.cell_size': cannot read value '10 um'");
  expect_refused(fmt::format("check {} --set novalue", demo), "--set 'novalue': expected KEY=VALUE");
  const std::string quick = (fs::path(PBXMPM_EXAMPLES_DIR) / "paper" / "quick.toml").string();
  expect_refused(
      fmt::format("study {} --set 'run.temperature=\"300 K\"' --out {} --no-report", quick, (dir / "q").string()),
      "--set 'run.temperature': group 'temperature' varies this key");
}

// `pbxmpm check` validates the README's own study deck as the study would (every run deck built).
TEST_F(CommandLine, CheckValidatesAStudyDeck) {
  const Result r = pbxmpm("check " + (fs::path(PBXMPM_EXAMPLES_DIR) / "paper" / "quick.toml").string());
  EXPECT_EQ(r.code, 0) << r.output;
  EXPECT_NE(r.output.find("valid study 'paper-quick': 13 runs"), std::string::npos) << r.output;
  // --set as `pbxmpm study --set` takes it: applied to every run deck, checked like the deck, and a
  // key a group varies refused
  const std::string own = (fs::path(PBXMPM_EXAMPLES_DIR) / "own" / "binder_stiffer.toml").string();
  const Result ok = pbxmpm("check " + own + " --set 'grid.cell_size=\"40 um\"'");
  EXPECT_EQ(ok.code, 0) << ok.output;
  expect_refused("check " + own + " --set 'grid.colour=1'", "unknown key 'grid.colour'");
  expect_refused("check " + own + " --set 'run.temperature=\"300 K\"'",
                 "--set 'run.temperature': group 'reference' varies this key");
}

// analyze's numeric flags are checked, not ignored when out of range (they are read before the
// run directory, so a missing directory does not hide the error).
TEST_F(CommandLine, AnalyzeFlagsAreCheckedNotIgnored) {
  expect_refused("analyze " + dir.string() + " --strength-strain -0.03",
                 "--strength-strain: expected a finite number > 0");
  expect_refused("analyze " + dir.string() + " --window-tolerance nan",
                 "--window-tolerance: expected a finite number > 0");
  expect_refused("analyze " + dir.string() + " --ke-ie-limit -1", "--ke-ie-limit: expected a finite number >= 0");
}

// Thread counts and output folders: a clear message, no crash.
TEST_F(CommandLine, ThreadsAndOutputFolderAreChecked) {
  const std::string deck = (fs::path(PBXMPM_EXAMPLES_DIR) / "demo" / "elastic_block_die.toml").string();
  expect_refused("run " + deck + " --threads 0 -q", "1 to 1024");
  expect_refused("run " + deck + " --threads 100000 -q", "1 to 1024");
  expect_refused("run " + deck + " --out /proc/pbxmpm_cannot_be_here -q",
                 "file system error on '/proc/pbxmpm_cannot_be_here");
}

// A build without MPI refuses `pbxmpm run` under an MPI launcher before it writes (each rank
// would run the whole deck into one folder); a build with MPI splits the run over the ranks
// (tests/distributed/test_run_over_ranks.cpp).
TEST_F(CommandLine, RunUnderAnMpiLauncherWithoutMpiIsRefusedBeforeItWrites) {
  const std::string deck = (fs::path(PBXMPM_EXAMPLES_DIR) / "demo" / "elastic_block_die.toml").string();
  const std::string out = (dir / "out").string();
#ifndef PBXMPM_HAVE_MPI
  for (const char* launcher : {"OMPI_COMM_WORLD_SIZE", "PMI_SIZE"}) {
    // a short run, should the refusal ever let it go ahead
    const Result r = pbx::test::shell(
        fmt::format("{}=2 {{pbx}} run {} --out {} -q --set run.end_strain=0.003 --set 'grid.cell_size=\"50 um\"'",
                    launcher, deck, out));
    EXPECT_EQ(r.code, 2) << launcher << "\n" << r.output;
    EXPECT_NE(r.output.find("built without MPI: one run is one process"), std::string::npos) << r.output;
    EXPECT_FALSE(fs::exists(out)) << "the refused run made its folder";
  }
#endif
  // one rank: a run like any other
  const Result one = pbx::test::shell(fmt::format(
      "OMPI_COMM_WORLD_SIZE=1 {{pbx}} run {} --out {} -q --set run.end_strain=0.003 --set 'grid.cell_size=\"50 um\"'",
      deck, out));
  EXPECT_EQ(one.code, 0) << one.output;
  EXPECT_TRUE(fs::exists(fs::path(out) / "history.csv"));
}

// `pbxmpm material` checks the whole material table, as a run does.
TEST_F(CommandLine, MaterialCommandRefusesUnknownKeys) {
  const std::string deck = write("m.toml",
                                 "[materials.block]\nmodel = \"linear_elastic\"\ndensity = \"1.934 g/cm3\"\n"
                                 "bulk_modulus = \"10.59 GPa\"\nshear_modulus = \"11.5 GPa\"\nfoo = 3\n");
  expect_refused("material " + deck + " --material block --path uniaxial_strain --strain -0.01 --rate 100",
                 "unknown key 'materials.block.foo'");
  const std::string good = write("g.toml",
                                 "[materials.block]\nmodel = \"linear_elastic\"\ndensity = \"1.934 g/cm3\"\n"
                                 "bulk_modulus = \"10.59 GPa\"\nshear_modulus = \"11.5 GPa\"\n");
  const std::string load = "material " + good + " --material block --path uniaxial_strain --strain -0.01 --steps 10";
  EXPECT_EQ(pbxmpm(load + " --rate 100").code, 0);
  // the loading time is |strain|/rate: a second definition used to be ignored without a word
  expect_refused(load + " --rate 100 --duration 1", "give --rate or --duration, not both");
  expect_refused(load + " --rate 100 --temperature inf", "--temperature: must be a finite number");
}

// `pbxmpm pack` on a run deck packs its specimen as the run would (only [packing] is checked, and
// the deck's specimen.seed wins as in a run); an unwritable --out fails before any packing.
TEST_F(CommandLine, PackReadsARunDeckAndChecksItsOutputFolderFirst) {
  std::ifstream in(fs::path(PBXMPM_EXAMPLES_DIR) / "paper" / "base.toml");
  std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const auto at = text.find("seed = 1", text.find("[specimen]"));
  ASSERT_NE(at, std::string::npos);
  const std::string deck = write("base.toml", text.replace(at, 8, "seed = 7"));
  const Result r = pbxmpm("pack " + deck + " --out " + (dir / "p").string());
  EXPECT_EQ(r.code, 0) << r.output;
  EXPECT_NE(r.output.find("seed 7"), std::string::npos) << r.output;
  EXPECT_TRUE(fs::exists(dir / "p" / "packing.csv"));
  expect_refused("pack " + deck + " --out /proc/pbxmpm_cannot_be_here",
                 "file system error on '/proc/pbxmpm_cannot_be_here");
}

// `pbxmpm run --restart checkpoint.h5` with the checkpoint in the current folder continues the run
// there (the output folder was "", so nothing was written at all), and ends with the history of an
// uninterrupted run; a fresh run into that folder removes the old checkpoint.
TEST_F(CommandLine, RestartFromABareCheckpointNameWritesBesideIt) {
  const std::string deck = pbx::test::block_deck(100, 0.006);  // the engine tests' die column, to 0.6 % strain
  const std::string d = write("block.toml", deck);
  const fs::path whole = dir / "whole", part = dir / "part";
  ASSERT_EQ(pbxmpm(fmt::format("run {} --out {} -q", d, whole.string())).code, 0);
  ASSERT_EQ(pbxmpm(fmt::format("run {} --out {} -q --checkpoint-every 5", d, part.string())).code, 0);
  ASSERT_TRUE(fs::exists(part / "checkpoint.h5"));
  fs::remove(part / "run.json");  // the restart must write it again (with an empty --out it wrote nothing)
  {                               // start from the checkpoint's own folder, naming it bare
    const std::string cmd =
        fmt::format("cd '{}' && '{}' run --restart checkpoint.h5 -q 2>&1", part.string(), PBXMPM_BINARY);
    ASSERT_EQ(std::system(cmd.c_str()), 0) << cmd;
  }
  auto slurp = [](const fs::path& p) {
    std::ifstream f(p);
    return std::string(std::istreambuf_iterator<char>(f), {});
  };
  EXPECT_EQ(slurp(part / "history.csv"), slurp(whole / "history.csv"));
  EXPECT_NE(slurp(part / "run.json").find("\"restarts\": 1"), std::string::npos) << slurp(part / "run.json");
  ASSERT_EQ(pbxmpm(fmt::format("run {} --out {} -q", d, part.string())).code, 0);
  EXPECT_FALSE(fs::exists(part / "checkpoint.h5")) << "a fresh run kept the earlier run's checkpoint";
}

// A run or a study into a folder another pbxmpm process is writing is refused before it writes
// anything; this test holds the folder's lock as that other process would.
TEST_F(CommandLine, AFolderAnotherProcessWritesIsRefused) {
  const std::string deck = write("block.toml", pbx::test::block_deck(100, 0.005));
  const fs::path busy = dir / "busy";
  {
    pbx::OutputLock held(busy, "run");
    expect_refused(fmt::format("run {} --out {} -q", deck, busy.string()),
                   fmt::format("another pbxmpm process (pid {}) is writing to '{}'", ::getpid(), busy.string()));
    EXPECT_FALSE(fs::exists(busy / "history.csv")) << "the refused run wrote into the folder";
    const std::string study = (fs::path(PBXMPM_EXAMPLES_DIR) / "paper" / "quick.toml").string();
    expect_refused(fmt::format("study {} --out {}", study, busy.string()), "give this study another output folder");
    EXPECT_FALSE(fs::exists(busy / "study.json")) << "the refused study wrote into the folder";
  }
  EXPECT_EQ(pbxmpm(fmt::format("run {} --out {} -q", deck, busy.string())).code, 0);
}

// Options that would be ignored are refused: analysis flags beside report --reuse-analysis (the
// runs' analysis.json files are used as they are), a deck beside run --restart (the checkpoint's
// own deck is the one that runs).
TEST_F(CommandLine, IgnoredOptionsAreRefused) {
  expect_refused(
      "report " + dir.string() + " --reuse-analysis --window 0.004:0.02",
      "report: --window changes the analysis, but --reuse-analysis uses the runs' analysis.json as they are");
  expect_refused("report " + dir.string() + " --reuse-analysis --options " + write("a.toml", "[analysis]\n"),
                 "report: --options changes the analysis");
  const std::string deck = write("block.toml", pbx::test::block_deck(100, 0.005));
  const fs::path part = dir / "part";
  ASSERT_EQ(pbxmpm(fmt::format("run {} --out {} -q --checkpoint-every 5", deck, part.string())).code, 0);
  expect_refused(fmt::format("run {} --restart {} -q", deck, (part / "checkpoint.h5").string()),
                 "give a deck or --restart CHECKPOINT, not both");
}

// tools/completion/pbxmpm.bash completes subcommands, each subcommand's options (read from the
// binary's own --help, so a new option is completed without editing the script) and file names.
TEST_F(CommandLine, BashCompletionOffersSubcommandsOptionsAndFiles) {
  const std::string script = (fs::path(PBXMPM_SOURCE_DIR) / "tools" / "completion" / "pbxmpm.bash").string();
  const std::string examples = PBXMPM_EXAMPLES_DIR;
  auto complete = [&](const std::string& words) {
    return pbx::test::shell(
        fmt::format("bash -c 'source \"{}\"; COMP_WORDS=({} {}); COMP_CWORD=$((${{#COMP_WORDS[@]}}-1)); _pbxmpm; "
                    "printf \"%s\\n\" \"${{COMPREPLY[@]}}\"'",
                    script, PBXMPM_BINARY, words));
  };
  pbx::test::Result r = complete("st");
  ASSERT_EQ(r.code, 0) << r.output;
  EXPECT_EQ(r.output, "study\nstatus\n");
  r = complete("run --checkpoint-m");
  EXPECT_EQ(r.output, "--checkpoint-minutes\n");
  r = complete("study --se");
  EXPECT_EQ(r.output, "--set\n");
  r = complete(fmt::format("check {}/paper/qui", examples));
  // compgen lists the files in directory order, which differs between file systems: compared sorted
  std::vector<std::string> files;
  std::istringstream lines(r.output);
  for (std::string line; std::getline(lines, line);) files.push_back(line);
  std::sort(files.begin(), files.end());
  EXPECT_EQ(files, (std::vector<std::string>{examples + "/paper/quick.toml", examples + "/paper/quick_bonds.toml",
                                             examples + "/paper/quick_grain_contact.toml",
                                             examples + "/paper/quick_joined.toml"}));
}

// `material` without --temperature drives the material at the deck's run temperature, or, in a
// deck without [run], at the material's own reference temperature (not at a fixed 293 K), and says
// which; --temperature overrides both (the banner is what is checked). A reference_temperature
// given to a model that takes none stays an unknown-key error.
TEST_F(CommandLine, MaterialTemperatureDefaultsToTheDecksOrTheMaterialsOwn) {
  const std::string deck = (dir / "m300.toml").string();
  std::ofstream(deck) << "[materials.m]\nmodel = \"viscoelastic_tait\"\ndensity = \"2.02 g/cm3\"\n"
                         "reference_temperature = \"300 K\"\nlong_term_shear_modulus = \"10 MPa\"\n"
                         "prony_shear_moduli = [\"10 MPa\"]\nprony_shear_times = [\"1e-5 s\"]\n"
                         "tait_c = 0.08936\ntait_k0 = \"0.27 GPa\"\n";
  const std::string load = " --material m --path uniaxial_strain --strain -1e-4 --duration 1e-4 --out -";
  Result r = pbxmpm("material " + deck + load);
  ASSERT_EQ(r.code, 0) << r.output;
  EXPECT_NE(r.output.find("at 300 K (the material's reference_temperature)"), std::string::npos) << r.output;
  r = pbxmpm("material " + deck + load + " --temperature 350");
  ASSERT_EQ(r.code, 0) << r.output;
  EXPECT_NE(r.output.find("at 350 K (--temperature)"), std::string::npos) << r.output;
  std::ofstream(deck, std::ios::app) << "[run]\ntemperature = \"320 K\"\n";
  r = pbxmpm("material " + deck + load);
  ASSERT_EQ(r.code, 0) << r.output;
  EXPECT_NE(r.output.find("at 320 K (the deck's run.temperature)"), std::string::npos) << r.output;
  const std::string elastic = (dir / "e300.toml").string();
  std::ofstream(elastic) << "[materials.m]\nmodel = \"linear_elastic\"\ndensity = \"1000 kg/m3\"\n"
                            "reference_temperature = \"300 K\"\nbulk_modulus = \"1 GPa\"\nshear_modulus = \"1 GPa\"\n";
  expect_refused("material " + elastic + load, "unknown key 'materials.m.reference_temperature'");
}

// `analyze STUDY/runs/<id>` reads the study's analysis.toml, as the study and its report did, and
// says so; --options overrides it. Here the study's table fixes the window by hand, which the
// automatic window would never give to the digit.
TEST_F(CommandLine, AnalyzeOfAStudyRunUsesTheStudysAnalysisOptions) {
  const fs::path results = fs::path(PBXMPM_EXAMPLES_DIR).parent_path() / "results" / "paper-quick";
  const fs::path run = dir / "study" / "runs" / "temperature-293K-s1";
  fs::create_directories(run);
  for (const char* f : {"history.csv", "run.json"})
    fs::copy_file(results / "runs" / "temperature-293K-s1" / f, run / f);
  fs::copy_file(results / "study.json", dir / "study" / "study.json");
  write("study/analysis.toml", "[analysis]\nlinear_window = [0.001, 0.003]\n");
  const Result r = pbxmpm("analyze " + run.string());
  ASSERT_EQ(r.code, 0) << r.output;
  EXPECT_NE(r.output.find("analysis options from " + (dir / "study" / "analysis.toml").string()), std::string::npos)
      << r.output;
  EXPECT_NE(r.output.find("linear window: strain 0.001 .. 0.003"), std::string::npos) << r.output;
  write("mine.toml", "[analysis]\nlinear_window = [0.002, 0.004]\n");
  const Result mine = pbxmpm("analyze " + run.string() + " --options " + (dir / "mine.toml").string());
  EXPECT_NE(mine.output.find("linear window: strain 0.002 .. 0.004"), std::string::npos) << mine.output;
}
