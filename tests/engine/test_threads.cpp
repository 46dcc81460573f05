// Results do not depend on the thread count: the strip-phased scatter and the chunked reductions
// fix the order of every floating-point sum, so 1 and 2 threads give bit-identical histories.
#include <omp.h>

#include <gtest/gtest.h>

#include "../contact/two_disks_deck.hpp"
#include "block_deck.hpp"
#include "scene_fixture.hpp"

using namespace pbx;

namespace {
std::vector<std::vector<double>> history(int threads) {
  Scene<2> sc = test::scene_from(test::block_deck(100, 0.01));
  RunOptions o = test::quiet();
  o.threads = threads;  // explicit: the automatic choice would give this small block one thread
  Runner<2> r(sc, o);
  std::vector<std::vector<double>> rows;
  r.run([&](const Measurement& m) { rows.push_back(Runner<2>::row_values(m, static_cast<int>(sc.bodies.size()))); });
  omp_set_num_threads(1);
  return rows;
}
}  // namespace

TEST(Threads, OneAndTwoThreadsGiveIdenticalHistories) {
  auto h1 = history(1), h2 = history(2);
  ASSERT_EQ(h1.size(), h2.size());
  for (std::size_t i = 0; i < h1.size(); ++i)
    for (std::size_t j = 0; j < h1[i].size(); ++j) EXPECT_EQ(h1[i][j], h2[i][j]) << "row " << i << " column " << j;
}

// The column above sits in one or two strips, so two threads never scatter at once and no
// particle leaves its strip. Here two disks on two fields cross a grid 80 cells wide (27 strips of
// 3 cells) at +-20 m/s and collide (multi-field contact): many strips are busy in each parity phase,
// and particles leave their home strips (strays, scattered serially after the phases). 1, 2 and 3
// threads must still give the same history to the bit.
TEST(Threads, CrossingDisksGiveIdenticalHistoriesWithStrays) {
  auto run = [](int threads, long& strays_seen) {
    Scene<2> sc = test::scene_from(test::two_disks_deck("frictionless", "8 us", 40));
    RunOptions o = test::quiet();
    o.threads = threads;
    Runner<2> r(sc, o);
    std::vector<std::vector<double>> rows;
    strays_seen = 0;
    r.run([&](const Measurement& m) {
      rows.push_back(Runner<2>::row_values(m, static_cast<int>(sc.bodies.size())));
      strays_seen = std::max(strays_seen, r.solver().stray_count());
    });
    omp_set_num_threads(1);
    return rows;
  };
  long s1 = 0, s2 = 0, s3 = 0;
  const auto h1 = run(1, s1), h2 = run(2, s2), h3 = run(3, s3);
  EXPECT_GT(s1, 0) << "no particle left its strip: the test exercises nothing beyond the column";
  EXPECT_EQ(s1, s2);
  EXPECT_EQ(s1, s3);
  ASSERT_EQ(h1.size(), h2.size());
  ASSERT_EQ(h1.size(), h3.size());
  for (std::size_t i = 0; i < h1.size(); ++i)
    for (std::size_t j = 0; j < h1[i].size(); ++j) {
      EXPECT_EQ(h1[i][j], h2[i][j]) << "2 threads, row " << i << " column " << j;
      EXPECT_EQ(h1[i][j], h3[i][j]) << "3 threads, row " << i << " column " << j;
    }
  std::printf("crossing disks: up to %ld strays\n", s1);
}
