#pragma once
// Deterministic parallel reductions. A sum is cut into parts whose extent does not depend on the
// thread count (fixed-size chunks of a range, or the grid's strips), each part is accumulated in
// order, and the parts are summed in part order: a run gives bit-identical results on 1 or N
// threads. In a run decomposed over ranks (docs/architecture.md, "One run over many ranks") each
// rank makes the parts it holds, a contiguous range of them, and the parts of every rank are
// gathered in rank order before the same sum: the bits do not depend on the rank count either.
#include <cstddef>
#include <functional>
#include <stdexcept>
#include <type_traits>
#include <vector>

namespace pbx {

// The ranks of a decomposed run as a reduction sees them: in_rank_order(mine) returns the doubles
// of every rank's parts, concatenated in rank order (an all-gather; every rank gets them).
class PartGather {
 public:
  virtual ~PartGather() = default;
  virtual std::vector<double> in_rank_order(const std::vector<double>& mine) = 0;
};

// Calls f on every double of a part, in a fixed order: a part type T other than double says which
// by a member each_double(f). A part travels between ranks as these doubles.
template <class T, class F>
void each_double(T& t, F&& f) {
  if constexpr (std::is_same_v<T, double>)
    f(t);
  else
    t.each_double(f);
}

// A part's doubles, part after part (what a rank sends of a sum).
template <class T>
std::vector<double> flatten_parts(std::vector<T>& parts) {
  std::vector<double> flat;
  for (auto& p : parts) each_double(p, [&](double& x) { flat.push_back(x); });
  return flat;
}

// zero + the parts whose doubles `all` holds, in their order (every part has the doubles of `zero`).
template <class T>
T sum_flat_parts(const std::vector<double>& all, const T& zero) {
  T sum = zero;
  T part = zero;
  std::size_t size = 0;
  each_double(part, [&](double&) { ++size; });
  if (size == 0 ? !all.empty() : all.size() % size != 0)
    throw std::logic_error("sum_parts: the ranks' parts are not whole parts");
  for (std::size_t k = 0; k < all.size();) {
    each_double(part, [&](double& x) { x = all[k++]; });
    sum += part;
  }
  return sum;
}

// zero + parts[0] + parts[1] + ..., with every rank's parts in between when `gather` is set (then
// `parts` are this rank's). Every part has the doubles of `zero` (a part's size is fixed).
template <class T>
T sum_parts(std::vector<T>& parts, const T& zero, PartGather* gather) {
  if (!gather) {
    T sum = zero;
    for (auto& p : parts) sum += p;
    return sum;
  }
  return sum_flat_parts(gather->in_rank_order(flatten_parts(parts)), zero);
}

// The sums nothing in the time step reads: a run's books (the contact's impulses, work and pair
// tally, friction and stress work, the springs' energy), which only a history row reads. One
// process books each at once. A decomposed run's ranks keep their doubles of each and gather them
// all in one all-gather at settle(), then book every sum in the order it was made: the same
// additions in the same order as one process, so the same bits, for one collective per history row
// (or per `batch` sums) instead of two per sum and step, where the ranks waited for each other in
// turn (its effect on the time was below what a noisy 2-vCPU VM resolves: docs/performance/engine.md,
// "Weak scaling, second pass").
class DeferredSums {
 public:
  // batch: a settle is taken when this many sums wait, a bound on the memory they hold; the same
  // sum of the same step on every rank, since every rank makes the same sums.
  explicit DeferredSums(PartGather* gather = nullptr, std::size_t batch = 256) : gather_(gather), batch_(batch) {}
  DeferredSums(const DeferredSums&) = delete;
  DeferredSums& operator=(const DeferredSums&) = delete;

  // a decomposed run's gather (null: one process), set before any sum waits
  void gather_through(PartGather* gather) {
    if (pending()) throw std::logic_error("DeferredSums: the gather changed while sums wait");
    gather_ = gather;
  }
  bool defers() const { return gather_ != nullptr; }
  bool pending() const { return !book_.empty(); }
  // `mine`: this rank's doubles of one gather (PartGather::in_rank_order); book(all) receives every
  // rank's, in rank order: at once in one process, at the next settle in a decomposed run.
  void add(std::vector<double> mine, std::function<void(const std::vector<double>&)> book) {
    if (!gather_) {
      book(mine);
      return;
    }
    len_.push_back(mine.size());
    data_.insert(data_.end(), mine.begin(), mine.end());
    book_.push_back(std::move(book));
    if (book_.size() >= batch_) settle();
  }
  // Collective in a decomposed run (every rank calls it at the same point of the run).
  void settle() {
    if (!gather_ || book_.empty()) return;  // every rank holds as many sums
    // this rank's message: the number of sums, each one's length, then their doubles
    std::vector<double> mine;
    mine.reserve(1 + len_.size() + data_.size());
    mine.push_back(static_cast<double>(len_.size()));
    for (const std::size_t n : len_) mine.push_back(static_cast<double>(n));
    mine.insert(mine.end(), data_.begin(), data_.end());
    const std::size_t n = len_.size();
    auto books = std::move(book_);
    book_.clear();
    len_.clear();
    data_.clear();
    const std::vector<double> all = gather_->in_rank_order(mine);
    // every rank's doubles of sum i, in rank order
    std::vector<std::vector<double>> of_sum(n);
    for (std::size_t at = 0; at < all.size();) {
      if (all[at] != static_cast<double>(n))
        throw std::logic_error("DeferredSums::settle: the ranks hold different numbers of sums");
      const std::size_t head = at + 1;
      std::size_t data = head + n;
      if (data > all.size()) throw std::logic_error("DeferredSums::settle: a rank's message is cut short");
      for (std::size_t i = 0; i < n; ++i) {
        const auto len = static_cast<std::size_t>(all[head + i]);
        if (data + len > all.size()) throw std::logic_error("DeferredSums::settle: a rank's message is cut short");
        of_sum[i].insert(of_sum[i].end(), all.begin() + static_cast<long>(data),
                         all.begin() + static_cast<long>(data + len));
        data += len;
      }
      at = data;
    }
    for (std::size_t i = 0; i < n; ++i) books[i](of_sum[i]);
  }

 private:
  PartGather* gather_;
  std::size_t batch_;
  std::vector<std::size_t> len_;  // this rank's doubles of each waiting sum
  std::vector<double> data_;      // and the doubles, sum after sum
  std::vector<std::function<void(const std::vector<double>&)>> book_;
};

}  // namespace pbx
