#pragma once
// Deterministic parallel reductions. A sum is cut into parts whose extent does not depend on the
// thread count (fixed-size chunks of a range, or the grid's strips), each part is accumulated in
// order, and the parts are summed in part order: a run gives bit-identical results on 1 or N
// threads. In a run decomposed over ranks (docs/architecture.md, "One run over many ranks") each
// rank makes the parts it holds, a contiguous range of them, and the parts of every rank are
// gathered in rank order before the same sum: the bits do not depend on the rank count either.
#include <cstddef>
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

// zero + parts[0] + parts[1] + ..., with every rank's parts in between when `gather` is set (then
// `parts` are this rank's). Every part has the doubles of `zero` (a part's size is fixed).
template <class T>
T sum_parts(std::vector<T>& parts, const T& zero, PartGather* gather) {
  T sum = zero;
  if (!gather) {
    for (auto& p : parts) sum += p;
    return sum;
  }
  std::vector<double> flat;
  for (auto& p : parts) each_double(p, [&](double& x) { flat.push_back(x); });
  const std::vector<double> all = gather->in_rank_order(flat);
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

}  // namespace pbx
