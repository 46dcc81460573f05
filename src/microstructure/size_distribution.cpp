#include "microstructure/size_distribution.hpp"

#include <cmath>
#include <numbers>

#include <fmt/format.h>

#include "core/error.hpp"

namespace pbx {

namespace {
double phi(double z) { return std::exp(-0.5 * z * z) / std::sqrt(2.0 * std::numbers::pi); }
double Phi(double z) { return 0.5 * std::erfc(-z / std::numbers::sqrt2); }
}  // namespace

double SizeDistribution::sample(int k, Rng& rng) const {
  const DiameterMode& m = modes[k];
  if (m.spread == 0) return m.mean;
  // Acceptance is Phi(b) - Phi(a), which read_packing_spec keeps above 1e-3.
  for (;;) {
    const double d = m.mean + m.spread * rng.normal();
    if (d >= dmin && d <= dmax) return d;
  }
}

double SizeDistribution::mode_cdf(int k, double d) const {
  const DiameterMode& m = modes[k];
  if (d < dmin) return 0;
  if (d >= dmax) return 1;
  if (m.spread == 0) return d >= m.mean ? 1 : 0;
  const double a = Phi((dmin - m.mean) / m.spread), b = Phi((dmax - m.mean) / m.spread);
  return (Phi((d - m.mean) / m.spread) - a) / (b - a);
}

double SizeDistribution::mode_mean_square(int k) const {
  const DiameterMode& m = modes[k];
  if (m.spread == 0) return m.mean * m.mean;
  // Truncated normal moments (Johnson, Kotz & Balakrishnan, Continuous Univariate Distributions 1,
  // sec. 10.1): with alpha, beta the standardised bounds and Z = Phi(beta) - Phi(alpha),
  // E[X] = mu + s (phi(a) - phi(b)) / Z, Var = s^2 [1 + (a phi(a) - b phi(b))/Z - ((phi(a) - phi(b))/Z)^2].
  const double a = (dmin - m.mean) / m.spread, b = (dmax - m.mean) / m.spread;
  const double Z = Phi(b) - Phi(a);
  const double r = (phi(a) - phi(b)) / Z;
  const double mean = m.mean + m.spread * r;
  const double var = m.spread * m.spread * (1.0 + (a * phi(a) - b * phi(b)) / Z - r * r);
  return var + mean * mean;
}

std::array<double, 2> SizeDistribution::count_fractions() const {
  if (!by_area) return {modes[0].share, modes[1].share};
  const double n0 = modes[0].share / mode_mean_square(0), n1 = modes[1].share / mode_mean_square(1);
  return {n0 / (n0 + n1), n1 / (n0 + n1)};
}

double SizeDistribution::cdf(double d) const {
  const auto c = count_fractions();
  return c[0] * mode_cdf(0, d) + c[1] * mode_cdf(1, d);
}

std::vector<SampledGrain> sample_diameters(const SizeDistribution& dist, double area, double tolerance, Rng& rng) {
  const double quarter_pi = 0.25 * std::numbers::pi;
  std::vector<SampledGrain> out;
  // Draws while the area is short of `target` by more than `tol`. A draw that would overshoot by
  // more than `tol` is replaced by a fresh one, so only the last grains are conditioned on the gap
  // they fill. closest = true instead stops before or after the draw, whichever is nearer.
  auto fill = [&](auto&& draw_mode, double target, double tol, bool closest) {
    double sum = 0;
    for (int rejected = 0; sum < target - tol && rejected < 100000;) {
      const int k = draw_mode();
      const double d = dist.sample(k, rng);
      const double a = quarter_pi * d * d;
      if (closest && sum + a > target) {
        if (sum + a - target > target - sum) break;
      } else if (!closest && sum + a > target + tol) {
        ++rejected;
        continue;
      }
      out.push_back({d, k});
      sum += a;
    }
    return sum;
  };
  double sum = 0;
  if (dist.by_area) {
    // The fine mode fills what the coarse one left, so the total tracks `area`.
    if (dist.modes[0].share > 0)
      sum = dist.modes[1].share > 0 ? fill([] { return 0; }, dist.modes[0].share * area, 0.0, true)
                                    : fill([] { return 0; }, area, tolerance, false);
    if (dist.modes[1].share > 0) sum += fill([] { return 1; }, area - sum, tolerance, false);
  } else {
    const double p0 = dist.modes[0].share;
    sum = fill([&] { return rng.uniform() < p0 ? 0 : 1; }, area, tolerance, false);
  }
  if (out.empty() || std::abs(sum - area) > tolerance)
    throw InputError(
        fmt::format("grains of the requested sizes cannot make up {:.4g} mm2 of TATB to within "
                    "{:.3g} mm2: use smaller grains or a larger box",
                    area * 1e6, tolerance * 1e6));
  return out;
}

}  // namespace pbx
