// DeferredSums (core/parallel.hpp): the books' sums of a decomposed run wait for one gather, then
// each is booked with every rank's doubles, in the order the sums were made.
#include <gtest/gtest.h>

#include <stdexcept>
#include <vector>

#include "core/parallel.hpp"

namespace pbx {
namespace {

// Two ranks seen from rank 0: the gather returns this rank's message, then rank 1's, and counts
// its calls (each is one collective of a real run).
class TwoRanks : public PartGather {
 public:
  explicit TwoRanks(std::vector<double> rank1) : rank1_(std::move(rank1)) {}
  std::vector<double> in_rank_order(const std::vector<double>& mine) override {
    ++calls;
    std::vector<double> all = mine;
    all.insert(all.end(), rank1_.begin(), rank1_.end());
    return all;
  }
  int calls = 0;

 private:
  std::vector<double> rank1_;
};

using Booked = std::vector<std::vector<double>>;

TEST(DeferredSums, EachSumIsBookedWithEveryRanksDoublesInTheOrderItWasMade) {
  // rank 1 made the same two sums: 3 doubles of the first, 2 of the second
  TwoRanks ranks({2, 3, 2, 10, 20, 30, 40, 50});
  DeferredSums sums(&ranks);
  Booked booked;
  sums.add({1, 2}, [&](const std::vector<double>& all) { booked.push_back(all); });
  sums.add({3}, [&](const std::vector<double>& all) { booked.push_back(all); });
  EXPECT_TRUE(sums.pending());
  EXPECT_TRUE(booked.empty()) << "a sum was booked before the ranks' doubles were gathered";
  EXPECT_EQ(ranks.calls, 0);
  sums.settle();
  EXPECT_EQ(ranks.calls, 1) << "one gather for every waiting sum";
  EXPECT_EQ(booked, (Booked{{1, 2, 10, 20, 30}, {3, 40, 50}}));
  EXPECT_FALSE(sums.pending());
  sums.settle();  // nothing waits: no collective (every rank holds as many sums)
  EXPECT_EQ(ranks.calls, 1);
}

TEST(DeferredSums, ABatchOfSumsIsSettledWhenItIsFull) {
  TwoRanks ranks({3, 1, 1, 1, 7, 8, 9});
  DeferredSums sums(&ranks, 3);
  Booked booked;
  for (double x : {4.0, 5.0, 6.0}) sums.add({x}, [&](const std::vector<double>& all) { booked.push_back(all); });
  EXPECT_EQ(ranks.calls, 1);
  EXPECT_FALSE(sums.pending());
  EXPECT_EQ(booked, (Booked{{4, 7}, {5, 8}, {6, 9}}));
}

TEST(DeferredSums, OneProcessBooksAtOnce) {
  DeferredSums sums;
  Booked booked;
  sums.add({1, 2}, [&](const std::vector<double>& all) { booked.push_back(all); });
  EXPECT_FALSE(sums.pending());
  EXPECT_EQ(booked, (Booked{{1, 2}}));
}

TEST(DeferredSums, RanksHoldingDifferentSumsAreRefused) {
  TwoRanks ranks({1, 1, 7});  // rank 1 made one sum, this rank two
  DeferredSums sums(&ranks);
  sums.add({1}, [](const std::vector<double>&) {});
  sums.add({2}, [](const std::vector<double>&) {});
  EXPECT_THROW(sums.settle(), std::logic_error);
  TwoRanks cut({2, 1, 5, 7});  // rank 1 says 1 + 5 doubles, sends 1
  DeferredSums short_message(&cut);
  short_message.add({1}, [](const std::vector<double>&) {});
  short_message.add({2}, [](const std::vector<double>&) {});
  EXPECT_THROW(short_message.settle(), std::logic_error);
  // and the gather cannot change under waiting sums
  DeferredSums waiting(&ranks);
  waiting.add({1}, [](const std::vector<double>&) {});
  EXPECT_THROW(waiting.gather_through(nullptr), std::logic_error);
}

// A fold's sum booked later is the sum made at once, to the bit: the parts are summed in the same
// order (zero, then part after part in strip and rank order).
TEST(DeferredSums, AFoldBookedLaterIsTheFoldOfNow) {
  std::vector<double> parts = {0.1, 1e16, -1e16, 0.3, 0.7};  // order matters in floating point
  const double now = sum_parts(parts, 0.0, nullptr);
  TwoRanks none({});  // a single rank under the gather
  DeferredSums sums(&none);
  double later = -1;
  sums.add(flatten_parts(parts), [&](const std::vector<double>& all) { later = sum_flat_parts(all, 0.0); });
  sums.settle();
  // TwoRanks appends nothing, so rank 0's message is the whole gather: one sum, five doubles
  EXPECT_EQ(later, now);
  EXPECT_NE(now, 0.1 + 0.3 + 0.7 + (1e16 - 1e16)) << "the example does not depend on the order";
}

}  // namespace
}  // namespace pbx
