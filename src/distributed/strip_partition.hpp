#pragma once
// A run's strips shared out over ranks (docs/architecture.md, "One run over many ranks"): each rank
// owns a contiguous range of whole strips, so its particles are a contiguous range of the
// one-process storage order. Balanced by particle count; no MPI here.
#include <algorithm>
#include <stdexcept>
#include <string>
#include <vector>

namespace pbx {

struct StripPartition {
  std::vector<long> first;  // rank r owns strips [first[r], first[r + 1]); first.back() = strips

  long strips_of(int rank) const {
    return first[static_cast<std::size_t>(rank) + 1] - first[static_cast<std::size_t>(rank)];
  }
};

// strip_begin[s]: the storage index where strip s begins (strips + 1 entries, the last the particle
// count); every rank gets at least `min_strips` strips. Rank r's range ends at the first strip
// boundary at or after (r + 1)/ranks of the particles, moved as needed to leave every rank its
// minimum.
inline StripPartition partition_strips(const std::vector<long>& strip_begin, int ranks, long min_strips = 1) {
  const long strips = static_cast<long>(strip_begin.size()) - 1;
  if (ranks < 1) throw std::invalid_argument("partition_strips: no ranks");
  if (strips < ranks * min_strips)
    throw std::invalid_argument("partition_strips: " + std::to_string(strips) + " strips cannot give " +
                                std::to_string(ranks) + " ranks " + std::to_string(min_strips) + " each");
  const double n = static_cast<double>(strip_begin.back() - strip_begin.front());
  StripPartition p;
  p.first.assign(static_cast<std::size_t>(ranks) + 1, strips);
  p.first[0] = 0;
  long s = 0;
  for (int r = 1; r < ranks; ++r) {
    const double target = static_cast<double>(strip_begin.front()) + n * r / ranks;
    long e = s + min_strips;
    while (e < strips && static_cast<double>(strip_begin[static_cast<std::size_t>(e)]) < target) ++e;
    // leave the ranks after this one their minimum
    e = std::min(e, strips - (ranks - r) * min_strips);
    e = std::max(e, s + min_strips);
    p.first[static_cast<std::size_t>(r)] = e;
    s = e;
  }
  return p;
}

}  // namespace pbx
