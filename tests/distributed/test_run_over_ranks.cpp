// `mpirun -n N pbxmpm run DECK` (issue 28): one run split over ranks writes the one-process run's
// history.csv byte for byte, with particles leaving their home strips (the strays' zone exchange),
// contact between fields across the cut between ranks, and every sum of the history (reactions,
// energies, contact forces, field overlap) taken strip by strip over the ranks.
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <utility>
#include <vector>

#include <fmt/format.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include "../deck_parts.hpp"
#include "io/json.hpp"

namespace fs = std::filesystem;

namespace {

struct Result {
  int code = -1;
  std::string output;
};

Result shell(const std::string& line) {
  FILE* p = popen((line + " 2>&1").c_str(), "r");
  Result r;
  if (!p) return r;
  char buf[4096];
  std::size_t k;
  while ((k = fread(buf, 1, sizeof buf, p)) > 0) r.output.append(buf, k);
  const int status = pclose(p);
  r.code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return r;
}

std::string read(const fs::path& f) {
  std::ifstream in(f, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

// Two elastic disks on two fields flying at each other along x at 20 m/s each and colliding under
// Coulomb friction, 10 um cells: strips 3 cells wide, so in 1.5 us (1.5 cells of travel) a third
// of the particles leave their home strip, within the next one. The disks meet at x = 0.2 mm,
// where the strips are cut between 2 ranks (the particles split evenly).
std::string colliding_disks_deck() {
  return R"(# two disks colliding head-on (units in the values)
[run]
end_time = "1.5 us"
history_points = 40
snapshots = 1
[grid]
cell_size = "10 um"
min = ["0 mm", "0 mm"]
max = ["0.4 mm", "0.2 mm"]
[contact]
default = "coulomb"
friction = 0.3
[[geometry]]
shape = "disk"
center = ["0.135 mm", "0.105 mm"]
radius = "0.06 mm"
material = "left"
velocity = ["20 m/s", "3 m/s"]
[[geometry]]
shape = "disk"
center = ["0.265 mm", "0.095 mm"]
radius = "0.06 mm"
material = "right"
velocity = ["-20 m/s", "0 m/s"]
)" + pbx::test::elastic("left", 1.9, 2, 0.3) +
         pbx::test::elastic("right", 1.9, 3, 0.3);
}

// A fresh folder holding the colliding disks' deck, removed after the test; `run(ranks, args)` runs
// `pbxmpm run ARGS` on one process (ranks = 1, no launcher) or under mpirun, one thread per process.
class RunOverRanks : public ::testing::Test {
 protected:
  void SetUp() override {
    if (std::system("command -v mpirun > /dev/null 2>&1") != 0) GTEST_SKIP() << "mpirun not installed";
    const auto* t = ::testing::UnitTest::GetInstance()->current_test_info();
    dir = fs::temp_directory_path() / fmt::format("pbx_{}_{}", t->name(), ::getpid());
    fs::remove_all(dir);
    fs::create_directories(dir);
    deck = (dir / "disks.toml").string();
    std::ofstream(deck) << colliding_disks_deck();
  }
  void TearDown() override {
    if (!dir.empty()) fs::remove_all(dir);
  }
  static Result run(int ranks, const std::string& args) {
    if (ranks == 1) return shell(fmt::format("OMP_NUM_THREADS=1 {} run {}", PBXMPM_BINARY, args));
    return shell(fmt::format(
        "OMP_NUM_THREADS=1 timeout 120 mpirun --allow-run-as-root --oversubscribe --bind-to none -n {} {} run {}",
        ranks, PBXMPM_BINARY, args));
  }
  fs::path dir;
  std::string deck;
};

}  // namespace

TEST_F(RunOverRanks, MpirunGivesTheOneProcessHistoryByteForByte) {
  const Result one = run(1, fmt::format("{} --out {} -q", deck, (dir / "one").string()));
  ASSERT_EQ(one.code, 0) << one.output;
  const std::string history = read(dir / "one" / "history.csv");
  ASSERT_GT(history.size(), 1000u);
  for (int n : {2, 3}) {
    const fs::path out = dir / fmt::format("ranks{}", n);
    const Result r = run(n, fmt::format("{} --out {} -q", deck, out.string()));
    ASSERT_EQ(r.code, 0) << n << " ranks:\n" << r.output;
    EXPECT_TRUE(read(out / "history.csv") == history) << n << " ranks: history.csv differs from one process's";
    // rank 0 wrote the files: run.json counts the whole specimen and the ranks
    const std::string json = read(out / "run.json");
    EXPECT_NE(json.find(fmt::format("\"mpi_ranks\": {}", n)), std::string::npos) << json.substr(0, 400);
    EXPECT_TRUE(fs::exists(out / "snapshots" / "snap_0001.h5"));
  }
}

// The paper specimen with the node film's gap binder joined to a grain (gap_binder = "join"): every
// rank builds the whole scene, joins the same binder particles, and drops the pairs the join used, so
// two ranks write the one process's history (the pairs themselves, film = "bonds", are refused over ranks).
TEST_F(RunOverRanks, PaperSpecimenWithJoinedGapBinderGivesTheOneProcessHistory) {
  const std::string args = fmt::format(
      "{}/paper/base.toml --set 'grid.cell_size=\"20 um\"' --set 'run.end_strain=0.0008' "
      "--set 'run.history_points=15' --set 'contact.pair=[{{ materials = [\"tatb\", \"tatb\"], law = "
      "\"binder_layer\", friction = 0.3, binder = \"f2314\", thickness = \"coats\", coat_scale = 1.64, film = "
      "\"integrated\", gap_binder = \"join\" }}]' -q --out ",
      PBXMPM_EXAMPLES_DIR);
  const Result one = run(1, args + (dir / "one").string());
  ASSERT_EQ(one.code, 0) << one.output;
  const Result two = run(2, args + (dir / "two").string());
  ASSERT_EQ(two.code, 0) << two.output;
  const std::string history = read(dir / "one" / "history.csv");
  ASSERT_GT(history.size(), 1000u);
  EXPECT_TRUE(read(dir / "two" / "history.csv") == history) << "history.csv on 2 ranks differs from one process's";
  // the join happened (20 um, seed 1: 397 binder particles)
  const pbx::Json spec = pbx::json_read_file((dir / "two" / "run.json").string())["specimen"];
  ASSERT_NE(pbx::json_find(spec, "film_gap_binder_particles_joined"), nullptr);
  EXPECT_GT(pbx::json_number(spec["film_gap_binder_particles_joined"]), 100.0);
  EXPECT_EQ(pbx::json_find(spec, "film_pairs"), nullptr);  // no springs on pairs
}

// The other shape functions over 2 ranks: bspline2, and the linear hat, whose exchange messages carry
// every entry of their lines (its gradient does not vanish with its weight, so an entry without
// mass may hold a force; StripExchange's `sparse`). The linear hat inverts a particle of these disks
// at step 51 (0.138 us, one process as two ranks: its cell-crossing error), so its runs stop at 0.12 us.
TEST_F(RunOverRanks, EveryShapeFunctionGivesTheOneProcessHistory) {
  for (const char* kernel : {"linear", "bspline2"}) {
    std::string set = fmt::format("--set 'grid.shape_function=\"{}\"'", kernel);
    if (std::string(kernel) == "linear") set += " --set 'run.end_time=\"0.12 us\"'";
    const Result one = run(1, fmt::format("{} {} --out {} -q", deck, set, (dir / kernel).string()));
    ASSERT_EQ(one.code, 0) << kernel << ":\n" << one.output;
    const fs::path out = dir / fmt::format("{}-ranks", kernel);
    const Result two = run(2, fmt::format("{} {} --out {} -q", deck, set, out.string()));
    ASSERT_EQ(two.code, 0) << kernel << ", 2 ranks:\n" << two.output;
    const std::string history = read(dir / kernel / "history.csv");
    ASSERT_GT(history.size(), 1000u) << kernel;
    EXPECT_TRUE(read(out / "history.csv") == history)
        << kernel << ": history.csv on 2 ranks differs from one process's";
  }
}

// A checkpoint written on 2 ranks is the one-process file: the run restarts from it on 1, 2 and 3
// ranks, and on 2 ranks from one a single process wrote, each finishing with the uninterrupted
// one-process history byte for byte (40 rows, checkpoints every 10: the restarts start at row 30).
TEST_F(RunOverRanks, CheckpointWrittenOnTwoRanksRestartsOnAnyNumber) {
  for (const auto& [name, ranks] : std::vector<std::pair<std::string, int>>{{"one", 1}, {"two", 2}}) {
    const Result r = run(ranks, fmt::format("{} --out {} -q --checkpoint-every 10", deck, (dir / name).string()));
    ASSERT_EQ(r.code, 0) << r.output;
    ASSERT_TRUE(fs::exists(dir / name / "checkpoint.h5"));
  }
  const std::string history = read(dir / "one" / "history.csv");
  for (const auto& [from, ranks] :
       std::vector<std::pair<std::string, int>>{{"two", 1}, {"two", 2}, {"two", 3}, {"one", 2}}) {
    const fs::path folder = dir / fmt::format("{}_on_{}", from, ranks);
    fs::copy(dir / from, folder, fs::copy_options::recursive);
    const Result r = run(ranks, fmt::format("--restart {} -q", (folder / "checkpoint.h5").string()));
    ASSERT_EQ(r.code, 0) << from << " on " << ranks << ":\n" << r.output;
    EXPECT_TRUE(read(folder / "history.csv") == history) << "checkpoint of '" << from << "' restarted on " << ranks;
    EXPECT_NE(read(folder / "run.json").find("\"restarts\": 1"), std::string::npos) << from << " on " << ranks;
  }
}

// In 3-D too: a cube in uniaxial strain between rigid bodies (examples/3d), strips along x.
TEST_F(RunOverRanks, ThreeDimensionalRunGivesTheOneProcessHistory) {
  const std::string cube = (fs::path(PBXMPM_EXAMPLES_DIR) / "3d" / "confined_cube.toml").string();
  for (int n : {1, 2}) {
    const Result r = run(n, fmt::format("{} --out {} -q", cube, (dir / std::to_string(n)).string()));
    ASSERT_EQ(r.code, 0) << r.output;
  }
  EXPECT_TRUE(read(dir / "1" / "history.csv") == read(dir / "2" / "history.csv"));
}

// Bad partitions are refused before the run, every rank with the same message; so are the options a
// run over ranks does not take yet (USF and MUSL).
TEST_F(RunOverRanks, MoreRanksThanTheGridAllowsAreRefused) {
  // 40 cells: 14 strips of 3, and a rank between two others needs 4 strips for its stray zones
  const Result r = run(5, fmt::format("{} --out {} -q", deck, (dir / "five").string()));
  EXPECT_EQ(r.code, 2) << r.output;
  EXPECT_NE(r.output.find("too few for 5 MPI ranks"), std::string::npos) << r.output;
  EXPECT_FALSE(fs::exists(dir / "five" / "history.csv"));
  const Result usf =
      run(2, fmt::format("{} --set 'solver.integrator=\"usf\"' --out {} -q", deck, (dir / "usf").string()));
  EXPECT_EQ(usf.code, 2) << usf.output;
  EXPECT_NE(usf.output.find("steps with \"usl\" only"), std::string::npos) << usf.output;
}
