#include "analysis/hashin_shtrikman.hpp"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "core/error.hpp"

namespace pbx {

namespace {
// Lambda(z) = [sum f_i / (K_i + 4z/3)]^-1 - 4z/3 ; Gamma(z) = [sum f_i / (G_i + z)]^-1 - z ;
// zeta(K, G) = G/6 (9K + 8G)/(K + 2G). Bounds: K+- = Lambda(G_max/min), G+- = Gamma(zeta(K,G)_max/min).
double bulk_bound(const std::vector<Phase>& ph, double z) {
  double s = 0;
  for (const auto& p : ph) {
    if (p.volume_fraction == 0) continue;
    const double d = p.bulk_modulus + 4.0 * z / 3.0;
    if (d == 0) return 0.0;  // a pore with z = 0: the lower bound of a porous body
    s += p.volume_fraction / d;
  }
  return 1.0 / s - 4.0 * z / 3.0;
}
double shear_bound(const std::vector<Phase>& ph, double z) {
  double s = 0;
  for (const auto& p : ph) {
    if (p.volume_fraction == 0) continue;
    const double d = p.shear_modulus + z;
    if (d == 0) return 0.0;
    s += p.volume_fraction / d;
  }
  return 1.0 / s - z;
}
double zeta(double K, double G) { return (K + 2.0 * G) > 0 ? G / 6.0 * (9.0 * K + 8.0 * G) / (K + 2.0 * G) : 0.0; }
}  // namespace

HashinShtrikmanBounds hashin_shtrikman_bounds(const std::vector<Phase>& ph) {
  if (ph.empty()) throw InputError("Hashin-Shtrikman bounds: no phases");
  double sum = 0;
  for (const auto& p : ph) {
    if (p.volume_fraction < 0 || p.bulk_modulus < 0 || p.shear_modulus < 0) {
      throw InputError("Hashin-Shtrikman bounds: moduli and volume fractions must be >= 0");
    }
    sum += p.volume_fraction;
  }
  if (std::fabs(sum - 1.0) > 1e-6) {
    throw InputError(fmt::format("Hashin-Shtrikman bounds: volume fractions sum to {}, not 1", sum));
  }
  double Gmax = 0, Gmin = HUGE_VAL, zmax = 0, zmin = HUGE_VAL;
  for (const auto& p : ph) {
    if (p.volume_fraction == 0) continue;
    Gmax = std::max(Gmax, p.shear_modulus);
    Gmin = std::min(Gmin, p.shear_modulus);
  }
  // zeta is evaluated with the extreme K and G taken separately (Berryman 1995).
  double Kmax = 0, Kmin = HUGE_VAL;
  for (const auto& p : ph) {
    if (p.volume_fraction == 0) continue;
    Kmax = std::max(Kmax, p.bulk_modulus);
    Kmin = std::min(Kmin, p.bulk_modulus);
  }
  zmax = zeta(Kmax, Gmax);
  zmin = zeta(Kmin, Gmin);
  HashinShtrikmanBounds b;
  b.K_upper = bulk_bound(ph, Gmax);
  b.K_lower = bulk_bound(ph, Gmin);
  b.G_upper = shear_bound(ph, zmax);
  b.G_lower = shear_bound(ph, zmin);
  return b;
}

}  // namespace pbx
