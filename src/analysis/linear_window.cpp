#include "analysis/linear_window.hpp"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "analysis/least_squares.hpp"
#include "analysis/stress_strain_curve.hpp"
#include "core/error.hpp"

namespace pbx {

LinearWindow find_linear_window(const std::vector<double>& strain, const std::vector<double>& stress,
                                const LinearWindowOptions& opt) {
  std::vector<std::size_t> idx = points_in(strain, opt.start, opt.max_strain);
  std::erase_if(idx, [&](std::size_t i) { return !std::isfinite(stress[i]); });
  if (opt.min_points < 3) throw InputError("linear window: min_points must be >= 3");
  if (static_cast<int>(idx.size()) < opt.min_points) {
    throw InputError(
        fmt::format("linear window: only {} points between strain {} and {} (need {}); "
                    "the run is too short or too coarsely sampled, or set the window by hand",
                    idx.size(), opt.start, opt.max_strain, opt.min_points));
  }
  // Running sums make each trial fit O(1); only the tail residuals need a loop.
  double sx = 0, sy = 0, sxx = 0, sxy = 0;
  std::size_t best = 0;
  int failures = 0;
  for (std::size_t k = 0; k < idx.size(); ++k) {
    const double x = strain[idx[k]], y = stress[idx[k]];
    sx += x;
    sy += y;
    sxx += x * x;
    sxy += x * y;
    const double n = double(k + 1);
    if (int(k + 1) < opt.min_points || x - strain[idx[0]] < opt.min_span) continue;
    const double den = n * sxx - sx * sx;
    if (den <= 0) continue;
    const double slope = (n * sxy - sx * sy) / den;
    // Tangent slope at the end of the window: a line through its last max(5, 1/3) points.
    const std::size_t tail = std::max<std::size_t>(5, (k + 1) / 3);
    double tx = 0, ty = 0, txx = 0, txy = 0;
    for (std::size_t q = k + 1 - tail; q <= k; ++q) {
      const double u = strain[idx[q]], v = stress[idx[q]];
      tx += u;
      ty += v;
      txx += u * u;
      txy += u * v;
    }
    const double tden = double(tail) * txx - tx * tx;
    const double tail_slope = tden > 0 ? (double(tail) * txy - tx * ty) / tden : slope;
    if (!(slope > 0) || tail_slope < (1.0 - opt.tolerance) * slope) {
      // One low tangent can be noise; two in a row end the window at the last good point.
      if (++failures < 2) continue;
      if (best == 0) best = k - 1;  // even the shortest window bends: keep it, and say so
      break;
    }
    failures = 0;
    best = k;
  }
  // Never below the minimum window: a first failed test at the last point used to leave a
  // one-point window (moduli NaN) without the note below.
  std::size_t floor = static_cast<std::size_t>(opt.min_points - 1);
  while (floor + 1 < idx.size() && strain[idx[floor]] - strain[idx[0]] < opt.min_span) ++floor;
  best = std::max(best, floor);
  // The tangent test reacts only once several points lie past the knee. Trim them: fit the first
  // two thirds of the window, and end it before the first later point that falls below that line
  // by more than max(4 rms, 0.2 % of its stress).
  const std::size_t base = std::max<std::size_t>(3, (best + 1) * 2 / 3);
  if (base < best + 1) {
    std::vector<double> bx, by;
    for (std::size_t q = 0; q < base; ++q) {
      bx.push_back(strain[idx[q]]);
      by.push_back(stress[idx[q]]);
    }
    const LineFit f = fit_line(bx, by);
    for (std::size_t q = base; q <= best; ++q) {
      const double r = stress[idx[q]] - (f.intercept + f.slope * strain[idx[q]]);
      if (r < -std::max(4.0 * f.rms_residual, 2e-3 * std::fabs(stress[idx[q]]))) {
        best = std::max(q - 1, floor);
        break;
      }
    }
  }
  LinearWindow w;
  w.lo = strain[idx[0]];
  w.hi = strain[idx[best]];
  w.points = int(best + 1);
  if (strain[idx.back()] - strain[idx[0]] < opt.min_span) {
    w.note = fmt::format(
        "the linear window takes every point from strain {} to {}, which span less than window_min_span ({}): "
        "the run is too short, or settles too late, for a window of that span",
        strain[idx[0]], strain[idx.back()], opt.min_span);
  } else if (best <= floor) {
    w.note = "the linear window is the minimum size: the curve bends (or is noisy) right after the start";
  }
  return w;
}

}  // namespace pbx
