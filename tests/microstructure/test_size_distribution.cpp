// Diameter sampling against the requested distribution: Kolmogorov-Smirnov at the 1 % level.
#include <algorithm>
#include <cmath>

#include <gtest/gtest.h>

#include "microstructure/size_distribution.hpp"

using namespace pbx;

namespace {

// KS statistic D = sup |F_n(x) - F(x)| of a sample against a CDF.
template <class Cdf>
double ks_statistic(std::vector<double> x, Cdf cdf) {
  std::sort(x.begin(), x.end());
  const double n = static_cast<double>(x.size());
  double d = 0;
  for (std::size_t i = 0; i < x.size(); ++i) {
    const double f = cdf(x[i]);
    d = std::max({d, (i + 1) / n - f, f - i / n});
  }
  return d;
}
// Asymptotic critical value at level alpha: sqrt(-ln(alpha/2) / 2) / sqrt(n) (1.628/sqrt(n) at 1 %).
double ks_critical(double alpha, std::size_t n) {
  return std::sqrt(-0.5 * std::log(0.5 * alpha)) / std::sqrt(double(n));
}

SizeDistribution paper_like(bool by_area) {
  SizeDistribution s;
  s.dmin = 50e-6;
  s.dmax = 300e-6;
  s.modes[0] = {260e-6, 30e-6, 0.75};
  s.modes[1] = {70e-6, 20e-6, 0.25};
  s.by_area = by_area;
  return s;
}

}  // namespace

TEST(SizeDistribution, KsCriticalValueMatchesTable) { EXPECT_NEAR(ks_critical(0.01, 1), 1.6276, 1e-4); }

TEST(SizeDistribution, TruncatedMomentsMatchQuadrature) {
  const auto s = paper_like(true);
  for (int k = 0; k < 2; ++k) {
    // E[d^2] = ∫ d^2 dF, by the midpoint rule on the CDF.
    double m2 = 0;
    const int n = 200000;
    for (int i = 0; i < n; ++i) {
      const double a = s.dmin + (s.dmax - s.dmin) * i / n, b = s.dmin + (s.dmax - s.dmin) * (i + 1) / n;
      m2 += 0.25 * (a + b) * (a + b) * (s.mode_cdf(k, b) - s.mode_cdf(k, a));
    }
    EXPECT_NEAR(s.mode_mean_square(k) / m2, 1.0, 1e-6) << k;
  }
}

TEST(SizeDistribution, SampleByCountPassesKsAndWrongDistributionFails) {
  const auto s = paper_like(false);
  Rng rng(7);
  const auto sample = sample_diameters(s, 5.0e-5, 1e-9, rng);  // about 1200 grains
  std::vector<double> d;
  for (const auto& g : sample) d.push_back(g.diameter);
  ASSERT_GT(d.size(), 1000u);
  const double crit = ks_critical(0.01, d.size());
  EXPECT_LT(ks_statistic(d, [&](double x) { return s.cdf(x); }), crit);
  // The test must be able to fail: a fine mode 20 um larger, or coarse and fine shares swapped, are rejected.
  auto wrong = s;
  wrong.modes[1].mean += 20e-6;
  EXPECT_GT(ks_statistic(d, [&](double x) { return wrong.cdf(x); }), crit);
  auto swapped = s;
  std::swap(swapped.modes[0].share, swapped.modes[1].share);
  EXPECT_GT(ks_statistic(d, [&](double x) { return swapped.cdf(x); }), crit);
  for (double x : d) EXPECT_TRUE(x >= s.dmin && x <= s.dmax);
}

TEST(SizeDistribution, AreaSharesAreMetAndEachModePassesKs) {
  const auto s = paper_like(true);
  Rng rng(11);
  const double area = 1.0e-4;
  const auto sample = sample_diameters(s, area, 1e-9, rng);
  std::vector<double> d[2];
  double a[2] = {0, 0};
  for (const auto& g : sample) {
    d[g.mode].push_back(g.diameter);
    a[g.mode] += 0.25 * M_PI * g.diameter * g.diameter;
  }
  EXPECT_NEAR(a[0] + a[1], area, 1e-9);
  EXPECT_NEAR(a[0] / area, 0.75, 0.002);  // one coarse grain is 0.0005 of the area
  for (int k = 0; k < 2; ++k)
    EXPECT_LT(ks_statistic(d[k], [&](double x) { return s.mode_cdf(k, x); }), ks_critical(0.01, d[k].size())) << k;
  // Number fractions implied by the area shares.
  const auto c = s.count_fractions();
  EXPECT_NEAR(double(d[1].size()) / sample.size(), c[1], 0.02);
}
