#pragma once
// Bimodal grain-diameter distribution: two normal modes, each truncated to [dmin, dmax], mixed by
// share of area or of count. Sampling and the exact CDF live together so that the
// Kolmogorov-Smirnov check compares the sample with the very distribution it was drawn from.
#include <array>
#include <string>
#include <vector>

#include "microstructure/rng.hpp"

namespace pbx {

struct DiameterMode {
  double mean = 0;    // m, of the untruncated normal
  double spread = 0;  // m, its standard deviation (0 = every grain has the mean diameter)
  double share = 0;   // fraction of the grains' area or count (see SizeDistribution::by_area)
};

struct SizeDistribution {
  std::array<DiameterMode, 2> modes;  // [0] coarse, [1] fine (order is only a label)
  double dmin = 0, dmax = 0;          // m, truncation
  bool by_area = true;                // shares are area fractions (else number fractions)

  // One diameter of mode k, from the normal truncated to [dmin, dmax] by rejection.
  double sample(int k, Rng& rng) const;
  // CDF of mode k's truncated normal.
  double mode_cdf(int k, double d) const;
  // Mean of d^2 for mode k (exact for the truncated normal): converts area shares into counts.
  double mode_mean_square(int k) const;
  // Fraction of grains (by number) in each mode implied by the shares.
  std::array<double, 2> count_fractions() const;
  // CDF of one grain's diameter, counts mixed by count_fractions().
  double cdf(double d) const;
};

// Diameters (with their mode) whose total disk area is within `tolerance` of `area`. Area shares:
// each mode draws until its own area share is met; count shares: each grain picks its mode at random.
// Draws that would overshoot the total by more than the tolerance are redrawn.
struct SampledGrain {
  double diameter;
  int mode;
};
std::vector<SampledGrain> sample_diameters(const SizeDistribution& dist, double area, double tolerance, Rng& rng);

}  // namespace pbx
