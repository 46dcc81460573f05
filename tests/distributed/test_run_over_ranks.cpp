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
[materials.left]
model = "linear_elastic"
density = "1.9 g/cm3"
youngs_modulus = "2 GPa"
poisson_ratio = 0.3
[materials.right]
model = "linear_elastic"
density = "1.9 g/cm3"
youngs_modulus = "3 GPa"
poisson_ratio = 0.3
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
)";
}

}  // namespace

TEST(RunOverRanks, MpirunGivesTheOneProcessHistoryByteForByte) {
  if (std::system("command -v mpirun > /dev/null 2>&1") != 0) GTEST_SKIP() << "mpirun not installed";
  const fs::path dir = fs::temp_directory_path() / fmt::format("pbx_run_over_ranks_{}", ::getpid());
  fs::remove_all(dir);
  fs::create_directories(dir);
  const fs::path deck = dir / "disks.toml";
  std::ofstream(deck) << colliding_disks_deck();
  const Result one = shell(
      fmt::format("OMP_NUM_THREADS=1 {} run {} --out {} -q", PBXMPM_BINARY, deck.string(), (dir / "one").string()));
  ASSERT_EQ(one.code, 0) << one.output;
  const std::string history = read(dir / "one" / "history.csv");
  ASSERT_GT(history.size(), 1000u);
  for (int n : {2, 3}) {
    const fs::path out = dir / fmt::format("ranks{}", n);
    const Result r = shell(fmt::format(
        "OMP_NUM_THREADS=1 timeout 120 mpirun --allow-run-as-root --oversubscribe --bind-to none -n {} {} run {} "
        "--out {} -q",
        n, PBXMPM_BINARY, deck.string(), out.string()));
    ASSERT_EQ(r.code, 0) << n << " ranks:\n" << r.output;
    EXPECT_TRUE(read(out / "history.csv") == history) << n << " ranks: history.csv differs from one process's";
    // rank 0 wrote the files: run.json counts the whole specimen and the ranks
    const std::string run = read(out / "run.json");
    EXPECT_NE(run.find(fmt::format("\"mpi_ranks\": {}", n)), std::string::npos) << run.substr(0, 400);
    EXPECT_TRUE(fs::exists(out / "snapshots" / "snap_0001.h5"));
  }
  fs::remove_all(dir);
}

// A checkpoint written on 2 ranks is the one-process file: the run restarts from it on 1, 2 and 3
// ranks, and on 2 ranks from one a single process wrote, each finishing with the uninterrupted
// one-process history byte for byte (40 rows, checkpoints every 10: the restarts start at row 30).
TEST(RunOverRanks, CheckpointWrittenOnTwoRanksRestartsOnAnyNumber) {
  if (std::system("command -v mpirun > /dev/null 2>&1") != 0) GTEST_SKIP() << "mpirun not installed";
  const fs::path dir = fs::temp_directory_path() / fmt::format("pbx_run_over_ranks_ck_{}", ::getpid());
  fs::remove_all(dir);
  fs::create_directories(dir);
  const fs::path deck = dir / "disks.toml";
  std::ofstream(deck) << colliding_disks_deck();
  const std::string mpirun = "OMP_NUM_THREADS=1 timeout 120 mpirun --allow-run-as-root --oversubscribe --bind-to none";
  const Result one = shell(fmt::format("OMP_NUM_THREADS=1 {} run {} --out {} -q --checkpoint-every 10", PBXMPM_BINARY,
                                       deck.string(), (dir / "one").string()));
  ASSERT_EQ(one.code, 0) << one.output;
  const Result two = shell(fmt::format("{} -n 2 {} run {} --out {} -q --checkpoint-every 10", mpirun, PBXMPM_BINARY,
                                       deck.string(), (dir / "two").string()));
  ASSERT_EQ(two.code, 0) << two.output;
  const std::string history = read(dir / "one" / "history.csv");
  ASSERT_TRUE(fs::exists(dir / "two" / "checkpoint.h5"));
  for (const auto& [from, ranks] :
       std::vector<std::pair<std::string, int>>{{"two", 1}, {"two", 2}, {"two", 3}, {"one", 2}}) {
    const fs::path run = dir / fmt::format("{}_on_{}", from, ranks);
    fs::copy(dir / from, run, fs::copy_options::recursive);
    const std::string restart = fmt::format("{} run --restart {} -q", PBXMPM_BINARY, (run / "checkpoint.h5").string());
    const Result r =
        shell(ranks == 1 ? "OMP_NUM_THREADS=1 " + restart : fmt::format("{} -n {} {}", mpirun, ranks, restart));
    ASSERT_EQ(r.code, 0) << from << " on " << ranks << ":\n" << r.output;
    EXPECT_TRUE(read(run / "history.csv") == history) << "checkpoint of '" << from << "' restarted on " << ranks;
    EXPECT_NE(read(run / "run.json").find("\"restarts\": 1"), std::string::npos) << from << " on " << ranks;
  }
  fs::remove_all(dir);
}

// In 3-D too: a cube in uniaxial strain between rigid bodies (examples/3d), strips along x.
TEST(RunOverRanks, ThreeDimensionalRunGivesTheOneProcessHistory) {
  if (std::system("command -v mpirun > /dev/null 2>&1") != 0) GTEST_SKIP() << "mpirun not installed";
  const fs::path dir = fs::temp_directory_path() / fmt::format("pbx_run_over_ranks_3d_{}", ::getpid());
  fs::remove_all(dir);
  const std::string deck = (fs::path(PBXMPM_EXAMPLES_DIR) / "3d" / "confined_cube.toml").string();
  const Result one =
      shell(fmt::format("OMP_NUM_THREADS=1 {} run {} --out {} -q", PBXMPM_BINARY, deck, (dir / "one").string()));
  ASSERT_EQ(one.code, 0) << one.output;
  const Result two = shell(fmt::format(
      "OMP_NUM_THREADS=1 timeout 120 mpirun --allow-run-as-root --oversubscribe --bind-to none -n 2 {} run {} "
      "--out {} -q",
      PBXMPM_BINARY, deck, (dir / "two").string()));
  ASSERT_EQ(two.code, 0) << two.output;
  EXPECT_TRUE(read(dir / "one" / "history.csv") == read(dir / "two" / "history.csv"));
  fs::remove_all(dir);
}

// Bad partitions are refused before the run, every rank with the same message; so are the options a
// run over ranks does not take yet (USF and MUSL).
TEST(RunOverRanks, MoreRanksThanTheGridAllowsAreRefused) {
  if (std::system("command -v mpirun > /dev/null 2>&1") != 0) GTEST_SKIP() << "mpirun not installed";
  const fs::path dir = fs::temp_directory_path() / fmt::format("pbx_run_over_ranks_refused_{}", ::getpid());
  fs::remove_all(dir);
  fs::create_directories(dir);
  const fs::path deck = dir / "disks.toml";
  std::ofstream(deck) << colliding_disks_deck();
  // 40 cells: 13 strips of 3, and a rank between two others needs 4 strips for its stray zones
  const Result r = shell(fmt::format(
      "OMP_NUM_THREADS=1 timeout 120 mpirun --allow-run-as-root --oversubscribe --bind-to none -n 5 {} run {} "
      "--out {} -q",
      PBXMPM_BINARY, deck.string(), (dir / "five").string()));
  EXPECT_EQ(r.code, 2) << r.output;
  EXPECT_NE(r.output.find("too few for 5 MPI ranks"), std::string::npos) << r.output;
  EXPECT_FALSE(fs::exists(dir / "five" / "history.csv"));
  const std::string mpirun2 = fmt::format(
      "OMP_NUM_THREADS=1 timeout 120 mpirun --allow-run-as-root --oversubscribe --bind-to none -n 2 {} run {} ",
      PBXMPM_BINARY, deck.string());
  const Result usf = shell(mpirun2 + "--set 'solver.integrator=\"usf\"' --out " + (dir / "usf").string() + " -q");
  EXPECT_EQ(usf.code, 2) << usf.output;
  EXPECT_NE(usf.output.find("steps with \"usl\" only"), std::string::npos) << usf.output;
  fs::remove_all(dir);
}
