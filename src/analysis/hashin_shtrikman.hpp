#pragma once
// Hashin-Shtrikman bounds on the effective bulk and shear moduli of an isotropic mixture of
// isotropic phases (3-D; Berryman's form, valid for any number of phases and for phases that are
// not well ordered). Pores are a phase with K = G = 0, which makes the lower bounds zero.
#include <string>
#include <vector>

namespace pbx {

struct Phase {
  double bulk_modulus = 0;   // Pa
  double shear_modulus = 0;  // Pa
  double volume_fraction = 0;
  std::string name;  // for reports only (e.g. the deck's material name, "pores")
};

struct HashinShtrikmanBounds {
  double K_lower = 0, K_upper = 0;  // Pa
  double G_lower = 0, G_upper = 0;  // Pa
};

// Throws InputError if fractions are negative or do not sum to 1 within 1e-6.
HashinShtrikmanBounds hashin_shtrikman_bounds(const std::vector<Phase>& phases);

}  // namespace pbx
