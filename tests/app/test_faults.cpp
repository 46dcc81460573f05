// Faults tested like physics: a full disk (a file-size limit, `ulimit -f`, which needs no root),
// flipped bytes in a checkpoint, kill -9 and SIGINT at random points, a restart into another run's
// folder, an empty --out, a reused folder, a run shorter than its history rows. The rule each test
// holds: a result file is complete or absent, a damaged file is refused by name, and a resumed run
// ends with the uninterrupted run's history, byte for byte. Runs are a small elastic column in the
// die (3,840 particles, 0.2-2 s each).
#include <algorithm>
#include <array>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <random>
#include <string>
#include <thread>

#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <fmt/format.h>
#include <gtest/gtest.h>

#include "../engine/block_deck.hpp"
#include "binary_test.hpp"

extern char** environ;

namespace fs = std::filesystem;

namespace {

using pbx::test::Result;
using pbx::test::shell;

std::string slurp(const fs::path& p) {
  std::ifstream f(p, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(f), {});
}

// The elastic column of the engine tests, 20 cells wide (its checkpoint is about 590 kB, its
// history about 80 kB: a 300 kB file-size limit lets the history through and stops the checkpoint).
std::string column_deck(double end_strain = 0.006, double mass_scaling = 100, int snapshots = 0, int rows = 201,
                        double ramp_strain = 0.004) {
  std::string d = pbx::test::block_deck(mass_scaling, end_strain, "usl", "ugimp", 0.2, 0.48);
  auto set = [&](const std::string& from, const std::string& to) { d.replace(d.find(from), from.size(), to); };
  set("snapshots = 0", fmt::format("snapshots = {}", snapshots));
  set("history_points = 201", fmt::format("history_points = {}", rows));
  set("ramp_strain = 0.004", fmt::format("ramp_strain = {}", ramp_strain));
  return d;
}

std::string json_status(const fs::path& run_json) {
  const std::string t = slurp(run_json);
  const std::string key = "\"status\": \"";
  const auto at = t.find(key);
  if (at == std::string::npos) return "(no status)";
  return t.substr(at + key.size(), t.find('"', at + key.size()) - at - key.size());
}

// Starts pbxmpm with these arguments (output to `log`), returns its pid.
pid_t spawn(const std::vector<std::string>& args, const fs::path& log) {
  std::vector<std::string> all = {PBXMPM_BINARY};
  all.insert(all.end(), args.begin(), args.end());
  std::vector<char*> argv;
  for (auto& a : all) argv.push_back(a.data());
  argv.push_back(nullptr);
  posix_spawn_file_actions_t fa;
  posix_spawn_file_actions_init(&fa);
  posix_spawn_file_actions_addopen(&fa, 1, log.c_str(), O_WRONLY | O_CREAT | O_APPEND, 0644);
  posix_spawn_file_actions_adddup2(&fa, 1, 2);
  pid_t pid = -1;
  if (posix_spawn(&pid, PBXMPM_BINARY, &fa, nullptr, argv.data(), environ) != 0) pid = -1;
  posix_spawn_file_actions_destroy(&fa);
  return pid;
}

int wait_code(pid_t pid) {
  int status = 0;
  waitpid(pid, &status, 0);
  return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
}

class Faults : public pbx::test::BinaryTest {
 protected:
  Faults() : BinaryTest("pbx_test_faults_") {}
};

}  // namespace

// F1/F2: a checkpoint that does not fit (the size limit stands for a full disk) stops the run with
// the file named and exit code 4 (HDF5 wrote part of it, accepted it as whole, then crashed the
// process at exit with 139); no checkpoint.h5 or .tmp is left, and run.json says "failed".
TEST_F(Faults, ACheckpointThatDoesNotFitIsAbsentNotPartial) {
  const std::string deck = write("col.toml", column_deck());
  const Result r =
      shell(fmt::format("ulimit -f 300; {{pbx}} run {} --out {} -q --checkpoint-every 5", deck, (dir / "r").string()));
  EXPECT_EQ(r.code, 4) << r.output;
  EXPECT_NE(r.output.find("output error: cannot write '" + (dir / "r" / "checkpoint.h5").string() + "'"),
            std::string::npos)
      << r.output;
  EXPECT_EQ(r.output.find("HDF5-DIAG"), std::string::npos) << "an HDF5 error dump instead of one line:\n" << r.output;
  EXPECT_FALSE(fs::exists(dir / "r" / "checkpoint.h5"));
  EXPECT_FALSE(fs::exists(dir / "r" / "checkpoint.h5.tmp"));
  EXPECT_EQ(json_status(dir / "r" / "run.json"), "failed");
  EXPECT_NE(slurp(dir / "r" / "run.json").find("checkpoint.h5"), std::string::npos) << slurp(dir / "r" / "run.json");
}

// F4: a snapshot that does not fit is named, leaves no half file, and run.json says "failed" with
// the reason (it stayed "running", and the message named run.json.tmp).
TEST_F(Faults, ASnapshotThatDoesNotFitIsNamedAndAbsent) {
  const std::string deck = write("col.toml", column_deck(0.006, 100, 3));
  const Result r = shell(fmt::format("ulimit -f 300; {{pbx}} run {} --out {} -q", deck, (dir / "r").string()));
  EXPECT_EQ(r.code, 4) << r.output;
  const std::string snap = (dir / "r" / "snapshots" / "snap_0000.h5").string();
  EXPECT_NE(r.output.find("cannot write '" + snap + "'"), std::string::npos) << r.output;
  EXPECT_FALSE(fs::exists(snap));
  EXPECT_FALSE(fs::exists(snap + ".tmp"));
  EXPECT_EQ(json_status(dir / "r" / "run.json"), "failed");
  EXPECT_NE(slurp(dir / "r" / "run.json").find("snap_0000.h5"), std::string::npos) << slurp(dir / "r" / "run.json");
}

// F8: flipped bits anywhere in a checkpoint. Each flip is either refused with a message naming the
// checkpoint, or (a byte HDF5 does not read: padding, free space) gives exactly the uninterrupted
// history. Never a crash, never a different result with exit 0.
TEST_F(Faults, FlippedBitsInACheckpointAreRefusedOrHarmless) {
  const std::string deck = write("col.toml", column_deck());
  const fs::path ref = dir / "ref";
  ASSERT_EQ(shell(fmt::format("{{pbx}} run {} --out {} -q --checkpoint-every 100", deck, ref.string())).code, 0);
  const std::string good = slurp(ref / "checkpoint.h5"), history = slurp(ref / "history.csv");
  ASSERT_GT(good.size(), 500000u);
  std::mt19937 rng(20261204);
  int refused = 0;
  const int trials = 24;
  for (int k = 0; k < trials; ++k) {
    // half spread evenly over the file (data), half in its first 4 kB (HDF5's metadata)
    const std::size_t at =
        k % 2 == 0 ? good.size() * (k + 1) / (trials + 2) : std::uniform_int_distribution<std::size_t>(0, 4095)(rng);
    const fs::path run = dir / fmt::format("flip{}", k);
    fs::create_directories(run);
    fs::copy_file(ref / "history.csv", run / "history.csv");
    fs::copy_file(ref / "run.json", run / "run.json");
    std::string bad = good;
    bad[at] = static_cast<char>(bad[at] ^ (1 << (k % 8)));
    std::ofstream(run / "checkpoint.h5", std::ios::binary) << bad;
    const Result r = shell(fmt::format("{{pbx}} run --restart {} -q", (run / "checkpoint.h5").string()));
    ASSERT_LT(r.code, 128) << "byte " << at << ": crashed\n" << r.output;
    if (r.code == 0) {
      EXPECT_EQ(slurp(run / "history.csv"), history) << "byte " << at << ": a damaged checkpoint gave another history";
    } else {
      ++refused;
      EXPECT_EQ(r.code, 2) << r.output;
      EXPECT_NE(r.output.find((run / "checkpoint.h5").string()), std::string::npos) << r.output;
    }
  }
  // every flip in the particle data must be caught: at least the evenly spread half
  EXPECT_GE(refused, trials / 2);
}

// F3: --restart writes only into the checkpoint's own folder: `--out` naming another folder is
// refused, and a checkpoint copied into a folder holding another run is refused by run_id; the
// other run's history is untouched.
TEST_F(Faults, ARestartRefusesAnotherRunsFolder) {
  const std::string deck = write("col.toml", column_deck());
  const fs::path a = dir / "a", b = dir / "b";
  ASSERT_EQ(shell(fmt::format("{{pbx}} run {} --out {} -q --checkpoint-every 100", deck, a.string())).code, 0);
  ASSERT_EQ(shell(fmt::format("{{pbx}} run {} --out {} -q", deck, b.string())).code, 0);
  const std::string b_history = slurp(b / "history.csv");
  Result r = shell(fmt::format("{{pbx}} run --restart {} --out {} -q", (a / "checkpoint.h5").string(), b.string()));
  EXPECT_EQ(r.code, 2) << r.output;
  EXPECT_NE(r.output.find("--restart continues the run in the checkpoint's own folder"), std::string::npos) << r.output;
  fs::copy_file(a / "checkpoint.h5", b / "checkpoint.h5");
  r = shell(fmt::format("{{pbx}} run --restart {} -q", (b / "checkpoint.h5").string()));
  EXPECT_EQ(r.code, 2) << r.output;
  EXPECT_NE(r.output.find("holds another run"), std::string::npos) << r.output;
  EXPECT_EQ(slurp(b / "history.csv"), b_history);
  // the checkpoint's own folder still resumes (the --out naming it is accepted)
  r = shell(fmt::format("{{pbx}} run --restart {} --out {} -q", (a / "checkpoint.h5").string(), a.string()));
  EXPECT_EQ(r.code, 0) << r.output;
}

// F5: an empty --out (an unset shell variable) is refused before the run (it ran the whole
// simulation, wrote nothing and exited 0).
TEST_F(Faults, AnEmptyOutputFolderIsRefused) {
  const std::string deck = write("col.toml", column_deck());
  Result r = shell(fmt::format("cd {} && {{pbx}} run {} --out '' -q", dir.string(), deck));
  EXPECT_EQ(r.code, 2) << r.output;
  EXPECT_NE(r.output.find("--out: an empty folder name"), std::string::npos) << r.output;
  EXPECT_EQ(r.output.find("particles"), std::string::npos) << "the run started:\n" << r.output;
  const std::string study = (fs::path(PBXMPM_EXAMPLES_DIR) / "paper" / "quick.toml").string();
  r = shell(fmt::format("cd {} && {{pbx}} study {} --out '' -q", dir.string(), study));
  EXPECT_EQ(r.code, 2) << r.output;
  EXPECT_NE(r.output.find("--out: an empty folder name"), std::string::npos) << r.output;
  EXPECT_FALSE(fs::exists(dir / "out"));
}

// F6: a fresh run into a folder holding an earlier run replaces it: the earlier analysis.json,
// checkpoint and snapshots beyond the new run's count are gone (they were kept beside the new
// run's files and read as its own).
TEST_F(Faults, ANewRunInAReusedFolderLeavesNoneOfTheOldRunsFiles) {
  const fs::path r = dir / "r";
  const std::string five = write("five.toml", column_deck(0.006, 100, 5));
  ASSERT_EQ(shell(fmt::format("{{pbx}} run {} --out {} -q --checkpoint-every 100", five, r.string())).code, 0);
  ASSERT_EQ(shell(fmt::format("{{pbx}} analyze {}", r.string())).code, 0);
  ASSERT_TRUE(fs::exists(r / "analysis.json"));
  ASSERT_TRUE(fs::exists(r / "snapshots" / "snap_0005.h5"));
  std::ofstream(r / "notes.txt") << "the user's own file\n";
  const std::string two = write("two.toml", column_deck(0.006, 100, 2));
  ASSERT_EQ(shell(fmt::format("{{pbx}} run {} --out {} -q", two, r.string())).code, 0);
  EXPECT_FALSE(fs::exists(r / "analysis.json"));
  EXPECT_FALSE(fs::exists(r / "checkpoint.h5"));
  EXPECT_TRUE(fs::exists(r / "snapshots" / "snap_0002.h5"));
  EXPECT_FALSE(fs::exists(r / "snapshots" / "snap_0003.h5"));
  EXPECT_FALSE(fs::exists(r / "snapshots" / "snap_0005.h5"));
  EXPECT_TRUE(fs::exists(r / "notes.txt")) << "a file pbxmpm does not write was removed";
}

// F10: a run of fewer steps than history rows ends exactly at its end strain (the last step is
// shortened): here 1.5 stable steps, which overshot by a third of the stroke.
TEST_F(Faults, ARunShorterThanItsRowsEndsAtItsEndStrain) {
  // stable step 1.0926e-8 s at 0.3 m/s over 0.48 mm: end strain 1.025e-5 is 1.5 steps, no ramp
  const std::string deck = write("short.toml", column_deck(1.025e-5, 100, 0, 50, 0.0));
  const Result r = shell(fmt::format("{{pbx}} run {} --out {} -q", deck, (dir / "r").string()));
  ASSERT_EQ(r.code, 0) << r.output;
  const std::string h = slurp(dir / "r" / "history.csv");
  const std::string last = h.substr(h.rfind('\n', h.size() - 2) + 1);
  std::vector<double> v;
  for (std::size_t a = 0, b; a < last.size(); a = b + 1) {
    b = last.find(',', a);
    if (b == std::string::npos) b = last.size();
    v.push_back(std::stod(last.substr(a, b - a)));
  }
  ASSERT_GT(v.size(), 4u);
  EXPECT_EQ(v[0], 2) << "steps";
  EXPECT_NEAR(v[3], 1.025e-5, 1e-15) << "strain of the last row";
  EXPECT_EQ(json_status(dir / "r" / "run.json"), "finished");
}

// kill -9 at random points (ten, from a seeded generator): the run is continued from its last
// checkpoint (or started over when it had none) until it finishes, and its history equals the
// uninterrupted run's byte for byte. A kill during a checkpoint's write must leave the previous one.
TEST_F(Faults, RunsKilledAtRandomPointsResumeBitForBit) {
  const std::string deck = write("col.toml", column_deck(0.01, 10));
  const fs::path ref = dir / "ref";
  ASSERT_EQ(shell(fmt::format("{{pbx}} run {} --out {} -q", deck, ref.string())).code, 0);
  const std::string history = slurp(ref / "history.csv");
  std::mt19937 rng(4242);
  std::uniform_int_distribution<int> ms(50, 1500);
  for (int k = 0; k < 10; ++k) {
    const fs::path run = dir / fmt::format("k{}", k);
    const fs::path log = dir / fmt::format("k{}.log", k);
    pid_t pid = spawn({"run", deck, "--out", run.string(), "-q", "--checkpoint-every", "1"}, log);
    ASSERT_GT(pid, 0);
    std::this_thread::sleep_for(std::chrono::milliseconds(ms(rng)));
    kill(pid, SIGKILL);
    const int killed = wait_code(pid);
    int code = killed;
    if (killed != 0) {  // killed before the end: continue (or start again without a checkpoint)
      const bool has = fs::exists(run / "checkpoint.h5");
      pid = has ? spawn({"run", "--restart", (run / "checkpoint.h5").string(), "-q"}, log)
                : spawn({"run", deck, "--out", run.string(), "-q"}, log);
      code = wait_code(pid);
    }
    ASSERT_EQ(code, 0) << "trial " << k << ":\n" << slurp(log);
    EXPECT_EQ(slurp(run / "history.csv"), history) << "trial " << k << ":\n" << slurp(log);
    EXPECT_EQ(json_status(run / "run.json"), "finished") << "trial " << k;
  }
}

// SIGINT (Ctrl-C): the run finishes to its next history row, writes a checkpoint and run.json
// "interrupted" with the command that continues it, exits 130; continued, it ends with the
// uninterrupted history. (It used to die at once with run.json "running" and nothing to resume.)
TEST_F(Faults, CtrlCSavesACheckpointThatResumesBitForBit) {
  const std::string deck = write("col.toml", column_deck(0.01, 10));
  const fs::path ref = dir / "ref", run = dir / "run", log = dir / "run.log";
  ASSERT_EQ(shell(fmt::format("{{pbx}} run {} --out {} -q", deck, ref.string())).code, 0);
  const pid_t pid = spawn({"run", deck, "--out", run.string(), "-q"}, log);
  ASSERT_GT(pid, 0);
  // the signal once the time loop runs (a few rows written), not while the process starts: a
  // loaded machine must not turn the test into one of process start-up
  for (int k = 0; k < 1000; ++k) {
    const std::string h = slurp(run / "history.csv");
    if (std::count(h.begin(), h.end(), '\n') >= 5) break;
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  kill(pid, SIGINT);
  ASSERT_EQ(wait_code(pid), 130) << slurp(log);
  EXPECT_EQ(json_status(run / "run.json"), "interrupted");
  EXPECT_NE(slurp(log).find("continue with: pbxmpm run --restart " + (run / "checkpoint.h5").string()),
            std::string::npos)
      << slurp(log);
  ASSERT_TRUE(fs::exists(run / "checkpoint.h5"));
  const Result r = shell(fmt::format("{{pbx}} run --restart {} -q", (run / "checkpoint.h5").string()));
  ASSERT_EQ(r.code, 0) << r.output;
  EXPECT_EQ(slurp(run / "history.csv"), slurp(ref / "history.csv"));
  EXPECT_EQ(json_status(run / "run.json"), "finished");
}

// A study killed at random points (ten) and started again with the same command ends with every
// run's history equal to the uninterrupted study's, and never reports a run from a damaged file.
TEST_F(Faults, StudiesKilledAtRandomPointsResumeBitForBit) {
  write("base.toml", column_deck(0.01, 10));
  const std::string study = write("study.toml",
                                  "[study]\nname = \"kill\"\nbase = \"base.toml\"\n"
                                  "[[study.group]]\nname = \"ms\"\nkey = \"solver.mass_scaling\"\nvalues = [10, 20]\n");
  const fs::path ref = dir / "ref";
  const Result r0 =
      shell(fmt::format("{{pbx}} study {} --out {} -q --no-report --checkpoint-every 1", study, ref.string()));
  ASSERT_EQ(r0.code, 0) << r0.output;
  std::vector<std::string> ids;
  for (const auto& e : fs::directory_iterator(ref / "runs")) ids.push_back(e.path().filename().string());
  ASSERT_EQ(ids.size(), 2u);
  std::mt19937 rng(77);
  std::uniform_int_distribution<int> ms(100, 3000);
  for (int k = 0; k < 10; ++k) {
    const fs::path out = dir / fmt::format("s{}", k), log = dir / fmt::format("s{}.log", k);
    const std::vector<std::string> args = {
        "study", study, "--out", out.string(), "-q", "--no-report", "--checkpoint-every", "1"};
    pid_t pid = spawn(args, log);
    ASSERT_GT(pid, 0);
    std::this_thread::sleep_for(std::chrono::milliseconds(ms(rng)));
    kill(pid, SIGKILL);
    if (wait_code(pid) != 0) {
      pid = spawn(args, log);
      ASSERT_EQ(wait_code(pid), 0) << "trial " << k << ":\n" << slurp(log);
    }
    for (const auto& id : ids) {
      EXPECT_EQ(slurp(out / "runs" / id / "history.csv"), slurp(ref / "runs" / id / "history.csv"))
          << "trial " << k << ", " << id;
      EXPECT_EQ(json_status(out / "runs" / id / "run.json"), "finished") << "trial " << k << ", " << id;
      EXPECT_TRUE(fs::exists(out / "runs" / id / "analysis.json")) << "trial " << k << ", " << id;
    }
  }
}

// A stop signal that arrives after a run's last checkpoint row lets that run finish; the study must
// then stop before the next run (it used to start it: the signal was forgotten, and a study sent
// SIGTERM went on for every remaining run). Eight rows per run; the signal once the first run has
// written its seventh, so the next row is its last and no checkpoint is taken. The same command
// then finishes the study, with the uninterrupted study's histories.
TEST_F(Faults, ASignalAsARunFinishesStopsTheStudy) {
  write("base.toml", column_deck(0.01, 10, 0, 8));
  const std::string study = write("study.toml",
                                  "[study]\nname = \"sig\"\nbase = \"base.toml\"\n"
                                  "[[study.group]]\nname = \"ms\"\nkey = \"solver.mass_scaling\"\nvalues = [10, 20]\n"
                                  "[analysis]\nlinear_window = [0.004, 0.01]\n");  // eight rows: the window by hand
  const fs::path ref = dir / "ref", out = dir / "out", log = dir / "out.log";
  const Result r0 = shell(fmt::format("{{pbx}} study {} --out {} -q --no-report", study, ref.string()));
  ASSERT_EQ(r0.code, 0) << r0.output;
  const std::vector<std::string> args = {"study", study, "--out", out.string(), "-q", "--no-report"};
  const pid_t pid = spawn(args, log);
  ASSERT_GT(pid, 0);
  const fs::path first = out / "runs" / "ms-10-s1" / "history.csv";
  auto rows = [&] {
    const std::string h = slurp(first);
    return h.empty() ? 0L : std::count(h.begin(), h.end(), '\n') - 1;  // less the header
  };
  for (int k = 0; k < 60000 && rows() < 7; ++k) std::this_thread::sleep_for(std::chrono::milliseconds(2));
  ASSERT_EQ(rows(), 7) << slurp(log);
  kill(pid, SIGTERM);
  const int code = wait_code(pid);
  EXPECT_NE(code, 0) << slurp(log);
  EXPECT_NE(slurp(log).find("the study stops here"), std::string::npos) << slurp(log);
  EXPECT_FALSE(fs::exists(out / "runs" / "ms-20-s1" / "history.csv")) << "the second run was started:\n" << slurp(log);
  const pid_t again = spawn(args, log);
  ASSERT_EQ(wait_code(again), 0) << slurp(log);
  for (const char* id : {"ms-10-s1", "ms-20-s1"}) {
    EXPECT_EQ(slurp(out / "runs" / id / "history.csv"), slurp(ref / "runs" / id / "history.csv")) << id;
    EXPECT_EQ(json_status(out / "runs" / id / "run.json"), "finished") << id;
  }
}
