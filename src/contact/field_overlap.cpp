#include "contact/field_overlap.hpp"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "core/error.hpp"

namespace pbx {

namespace {
// Raster cap (pixels); a finer request is coarsened by powers of 2. 2^26 int32 = 256 MB.
constexpr long kMaxPixels = 1L << 26;
}  // namespace

FieldOverlap::FieldOverlap(const Grid<2>& g, double pixel) : pixel_(pixel), origin_(g.origin) {
  if (!(pixel > 0) || !std::isfinite(pixel))
    throw InputError(fmt::format("field overlap: pixel {} m must be > 0", pixel));
  const double wx = g.h * static_cast<double>(g.n[0] - 1), wy = g.h * static_cast<double>(g.n[1] - 1);
  while (std::ceil(wx / pixel_) * std::ceil(wy / pixel_) > static_cast<double>(kMaxPixels)) pixel_ *= 2.0;
  nx_ = static_cast<long>(std::ceil(wx / pixel_));
  ny_ = static_cast<long>(std::ceil(wy / pixel_));
  owner_.assign(static_cast<std::size_t>(nx_ * ny_), -1);
}

double FieldOverlap::default_pixel(const Particles<2>& P) {
  double v = HUGE_VAL;
  for (double v0 : P.volume0) v = std::min(v, v0);
  return P.size() ? 0.25 * std::sqrt(v) : 0.0;
}

double FieldOverlap::area(const Particles<2>& P, const std::function<void(std::vector<std::int32_t>&)>& merge) {
  std::fill(owner_.begin(), owner_.end(), -1);
  const double inv = 1.0 / pixel_;
  long shared = 0;
  // Pixel k covers [k, k+1) pixels from the origin. Candidates: the pixels whose centres lie in the
  // bounding box of the deformed domain, ceil(lo - 1/2) <= k < ceil(hi - 1/2), clamped in floating
  // point before the cast so a particle far outside the grid cannot overflow it. A centre c belongs
  // to the domain when xi = F^-1 (c - x) / s0 lies in [-1/2, 1/2)^2: half-open like the tiling, so
  // at F = I (edges half a pixel from the nearest centres) rounding never decides.
  auto range = [](double lo, double hi, long n, long& k0, long& k1) {
    const double top = static_cast<double>(n);
    k0 = static_cast<long>(std::clamp(std::ceil(lo - 0.5), 0.0, top));
    k1 = static_cast<long>(std::clamp(std::ceil(hi - 0.5), 0.0, top));
  };
  for (std::size_t p = 0; p < P.size(); ++p) {
    const Mat<2>& F = P.F[p];
    const double s0 = std::sqrt(std::max(P.volume0[p], 0.0)) * inv;  // initial side, pixels
    const double cx = (P.x[p][0] - origin_[0]) * inv, cy = (P.x[p][1] - origin_[1]) * inv;
    const double J = F.determinant();
    // a non-finite or inverted particle is skipped: the solver stops on those
    if (!std::isfinite(cx + cy + s0 + F.sum()) || !(J > 0) || !(s0 > 0)) continue;
    const double hx = 0.5 * s0 * (std::abs(F(0, 0)) + std::abs(F(0, 1)));
    const double hy = 0.5 * s0 * (std::abs(F(1, 0)) + std::abs(F(1, 1)));
    const Mat<2> G = F.inverse() / s0;
    long i0, i1, j0, j1;
    range(cx - hx, cx + hx, nx_, i0, i1);
    range(cy - hy, cy + hy, ny_, j0, j1);
    const std::int32_t f = P.field[p];
    for (long j = j0; j < j1; ++j) {
      std::int32_t* row = owner_.data() + j * nx_;
      const double dy = static_cast<double>(j) + 0.5 - cy;
      for (long i = i0; i < i1; ++i) {
        const double dx = static_cast<double>(i) + 0.5 - cx;
        const double a = G(0, 0) * dx + G(0, 1) * dy, b = G(1, 0) * dx + G(1, 1) * dy;
        if (a < -0.5 || a >= 0.5 || b < -0.5 || b >= 0.5) continue;
        const std::int32_t o = row[i];
        if (o == -1)
          row[i] = f;
        else if (o >= 0 && o != f)
          row[i] = -2, ++shared;
      }
    }
  }
  if (merge) {
    merge(owner_);
    shared = static_cast<long>(std::count(owner_.begin(), owner_.end(), std::int32_t{-2}));
  }
  return static_cast<double>(shared) * pixel_ * pixel_;
}

}  // namespace pbx
