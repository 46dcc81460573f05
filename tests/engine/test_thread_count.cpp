// The automatic thread count: one thread per kParticlesPerThread particles, at most this rank's
// share of the cores; an explicit count is kept, with a note when the scene is too small for it.
#include <gtest/gtest.h>

#include "run/thread_count.hpp"

using namespace pbx;

TEST(ThreadCount, AutomaticFollowsTheSceneSize) {
  // the quick study's 11,045 particles, the fine 176,820, the full 707,298 on 2 cores
  EXPECT_EQ(choose_threads(0, 11'045, false, 2, 2, 1).threads, 1);
  EXPECT_EQ(choose_threads(0, 99'999, false, 2, 2, 1).threads, 1);
  EXPECT_EQ(choose_threads(0, 100'000, false, 2, 2, 1).threads, 2);
  EXPECT_EQ(choose_threads(0, 176'820, false, 2, 2, 1).threads, 2);
  EXPECT_EQ(choose_threads(0, 707'298, false, 2, 2, 1).threads, 2);
  EXPECT_EQ(choose_threads(0, 707'298, false, 16, 16, 1).threads, 14);
  EXPECT_EQ(choose_threads(0, 0, false, 2, 2, 1).threads, 1);
  EXPECT_EQ(choose_threads(0, 11'045, false, 2, 2, 1).chosen_by, "auto");
  EXPECT_TRUE(choose_threads(0, 11'045, false, 2, 2, 1).note.empty());
}

TEST(ThreadCount, MpiRanksOnANodeShareItsCores) {
  // mpirun -n 2 on 2 cores: one thread per rank even for the full specimen (was 2 each: 4 on 2 cores)
  EXPECT_EQ(choose_threads(0, 707'298, false, 2, 2, 2).threads, 1);
  EXPECT_EQ(choose_threads(0, 707'298, false, 16, 16, 4).threads, 4);
  EXPECT_EQ(choose_threads(0, 707'298, false, 2, 2, 3).threads, 1);  // more ranks than cores
}

TEST(ThreadCount, ExplicitCountsAreKeptAndSmallScenesGetANote) {
  const ThreadChoice big = choose_threads(2, 707'298, false, 2, 2, 1);
  EXPECT_EQ(big.threads, 2);
  EXPECT_EQ(big.chosen_by, "--threads");
  EXPECT_TRUE(big.note.empty());
  const ThreadChoice small = choose_threads(2, 11'045, false, 2, 2, 1);
  EXPECT_EQ(small.threads, 2);
  EXPECT_NE(small.note.find("11045 particles on 2 threads (set by --threads)"), std::string::npos) << small.note;
  EXPECT_NE(small.note.find("would use 1"), std::string::npos) << small.note;
  const ThreadChoice env = choose_threads(0, 11'045, true, 2, 2, 1);
  EXPECT_EQ(env.threads, 2);
  EXPECT_EQ(env.chosen_by, "OMP_NUM_THREADS");
  EXPECT_FALSE(env.note.empty());
  EXPECT_TRUE(choose_threads(0, 11'045, true, 1, 2, 1).note.empty());  // CTest's OMP_NUM_THREADS=1
  EXPECT_TRUE(choose_threads(1, 11'045, false, 2, 2, 1).note.empty());
}
