// Results do not depend on the thread count: the strip-phased scatter and the chunked reductions
// fix the order of every floating-point sum, so 1 and 2 threads give bit-identical histories.
#include <omp.h>

#include <gtest/gtest.h>

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
