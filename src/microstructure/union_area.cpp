#include "microstructure/union_area.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace pbx {

namespace {

constexpr double kTwoPi = 2.0 * std::numbers::pi;

// Angular interval [a, b] (b - a <= 2 pi) on a circle, added to `out` normalised into [0, 2 pi).
void add_interval(std::vector<std::pair<double, double>>& out, double a, double b) {
  const double len = b - a;
  if (len >= kTwoPi) {
    out.emplace_back(0, kTwoPi);
    return;
  }
  if (len <= 0) return;
  a = std::fmod(a, kTwoPi);
  if (a < 0) a += kTwoPi;
  if (a + len <= kTwoPi) {
    out.emplace_back(a, a + len);
  } else {
    out.emplace_back(a, kTwoPi);
    out.emplace_back(0, a + len - kTwoPi);
  }
}

// Covered length of [lo, hi] by a set of intervals.
double covered(std::vector<std::pair<double, double>> iv, double lo, double hi) {
  std::sort(iv.begin(), iv.end());
  double len = 0, end = lo;
  for (auto [a, b] : iv) {
    a = std::max(a, end);
    b = std::min(b, hi);
    if (b > a) {
      len += b - a;
      end = b;
    }
  }
  return len;
}

}  // namespace

double union_area_in_box(const std::vector<Circle>& circles, const Eigen::Vector2d& box) {
  const double W = box.x(), H = box.y();
  double twice_area = 0;
  std::vector<std::pair<double, double>> right_edge, top_edge, cover;
  const std::size_t n = circles.size();
  for (std::size_t i = 0; i < n; ++i) {
    const Eigen::Vector2d& c = circles[i].c;
    const double R = circles[i].r;
    if (R <= 0 || c.x() + R <= 0 || c.x() - R >= W || c.y() + R <= 0 || c.y() - R >= H) continue;
    // Edge stretches inside this circle (only the right and top edges contribute to the integral:
    // on x = 0 and y = 0 the integrand x dy - y dx vanishes).
    if (std::abs(W - c.x()) < R) {
      const double h = std::sqrt(R * R - (W - c.x()) * (W - c.x()));
      right_edge.emplace_back(c.y() - h, c.y() + h);
    }
    if (std::abs(H - c.y()) < R) {
      const double h = std::sqrt(R * R - (H - c.y()) * (H - c.y()));
      top_edge.emplace_back(c.x() - h, c.x() + h);
    }
    cover.clear();
    bool hidden = false;
    for (std::size_t j = 0; j < n && !hidden; ++j) {
      if (j == i) continue;
      const double Rj = circles[j].r;
      const Eigen::Vector2d d = circles[j].c - c;
      const double dist = d.norm();
      if (dist >= R + Rj) continue;
      if (dist <= Rj - R) {  // inside j (ties: the lower index counts, so equal circles count once)
        if (dist < Rj - R || j < i) hidden = true;
        continue;
      }
      if (dist <= R - Rj) continue;  // j inside this circle: covers no arc of it
      const double mid = std::atan2(d.y(), d.x());
      const double half = std::acos(std::clamp((R * R + dist * dist - Rj * Rj) / (2 * R * dist), -1.0, 1.0));
      add_interval(cover, mid - half, mid + half);
    }
    if (hidden) continue;
    // Arcs outside the box do not bound the clipped set.
    auto outside = [&](double centre, double offset) {  // where cos(theta - centre) > offset / R
      if (offset / R >= 1) return;
      if (offset / R <= -1) {
        add_interval(cover, 0, kTwoPi);
        return;
      }
      const double half = std::acos(offset / R);
      add_interval(cover, centre - half, centre + half);
    };
    outside(0, W - c.x());                       // x > W
    outside(std::numbers::pi, c.x());            // x < 0
    outside(0.5 * std::numbers::pi, H - c.y());  // y > H
    outside(-0.5 * std::numbers::pi, c.y());     // y < 0
    std::sort(cover.begin(), cover.end());
    // Integrate over the uncovered arcs: 1/2 ∫ R^2 + R (cx cos t + cy sin t) dt.
    double t = 0;
    auto arc = [&](double a, double b) {
      if (b <= a) return;
      twice_area += R * R * (b - a) + R * (c.x() * (std::sin(b) - std::sin(a)) - c.y() * (std::cos(b) - std::cos(a)));
    };
    for (auto [a, b] : cover) {
      arc(t, a);
      t = std::max(t, b);
    }
    arc(t, kTwoPi);
  }
  // Box edges traversed anticlockwise: right edge upwards gives W dy, top edge leftwards -H dx.
  twice_area += W * covered(right_edge, 0, H) + H * covered(top_edge, 0, W);
  return 0.5 * twice_area;
}

}  // namespace pbx
