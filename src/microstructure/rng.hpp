#pragma once
// The packing's only source of randomness. std::mt19937_64 is fully specified by the standard, but
// std::uniform_real_distribution and std::normal_distribution are not (each standard library draws
// differently), so the distributions are written here: the same seed then gives the same packing
// with any compiler and library (up to the last bit of libm's log/cos in the normal draw).
#include <cmath>
#include <cstdint>
#include <numbers>
#include <random>

namespace pbx {

class Rng {
 public:
  explicit Rng(std::uint64_t seed) : engine_(seed) {}

  // Uniform on [0, 1) with 53 random bits.
  double uniform() { return static_cast<double>(engine_() >> 11) * 0x1.0p-53; }
  double uniform(double lo, double hi) { return lo + (hi - lo) * uniform(); }
  // Uniform integer in [0, n).
  std::uint64_t below(std::uint64_t n) { return static_cast<std::uint64_t>(uniform() * static_cast<double>(n)); }

  // Standard normal by the Box-Muller transform (one value per call, the pair's sine half unused,
  // which keeps the stream position independent of call history).
  double normal() {
    const double u1 = 1.0 - uniform();  // (0, 1]: log stays finite
    const double u2 = uniform();
    return std::sqrt(-2.0 * std::log(u1)) * std::cos(2.0 * std::numbers::pi * u2);
  }

 private:
  std::mt19937_64 engine_;
};

}  // namespace pbx
