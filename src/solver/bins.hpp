#pragma once
// Race-free, deterministic parallel scatter: particles are binned into vertical strips of
// `width` >= 3 cells. A particle's 3x3 stencil reaches one node column beyond its strip on
// each side, so strips of the same parity never touch the same node: even strips scatter in
// parallel, then odd strips. The sum order at every node is then fixed by the strip layout alone,
// so results are bit-identical for any thread count. Strip width does not depend on threads.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

namespace pbx {

struct StripBins {
  long width = 3;   // cells per strip
  long strips = 0;
  std::vector<std::vector<std::uint32_t>> members;

  void setup(long cells_x) {
    width = std::max(3L, cells_x / 32);
    strips = (cells_x + width - 1) / width;
    members.assign(static_cast<std::size_t>(strips), {});
  }
  long strip_of_cell(long cell_x) const { return std::min(strips - 1, std::max(0L, cell_x / width)); }
  // s: x-coordinate in cell units from the grid origin
  long strip_of(double s) const { return strip_of_cell(static_cast<long>(std::floor(s))); }
};

}  // namespace pbx
