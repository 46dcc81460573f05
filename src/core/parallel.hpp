#pragma once
// Deterministic parallel reductions: the range is cut into chunks whose size does not depend on
// the thread count, partial results are stored per chunk and summed in chunk order, so a run gives
// bit-identical results on 1 or N threads.
#include <vector>

#include <omp.h>

namespace pbx {

inline constexpr long kReduceChunk = 4096;

template <class T, class Body>
T ordered_reduce(long n, T zero, Body&& body, long chunk = kReduceChunk) {
  const long nchunks = (n + chunk - 1) / chunk;
  std::vector<T> partial(static_cast<std::size_t>(nchunks), zero);
#pragma omp parallel for schedule(static)
  for (long c = 0; c < nchunks; ++c) {
    const long b = c * chunk, e = std::min(n, b + chunk);
    partial[static_cast<std::size_t>(c)] = body(b, e);
  }
  T sum = zero;
  for (auto& p : partial) sum += p;
  return sum;
}

}  // namespace pbx
