#pragma once
// Paper Eq. 16-22, the "improved Hashin-Shtrikman" density law: M_eff / M^U = k (rho/rho0)^n,
// fitted as ln(M_eff/M^U) = ln k + n ln(rho/rho0) (Eq. 19, 20) by linear least squares.
#include <vector>

#include "analysis/least_squares.hpp"

namespace pbx {

// Parameters "k" and "n" (dimensionless). The interval of k is exp of that of ln k.
FitResult fit_density_law(const std::vector<double>& density, const std::vector<double>& modulus, double rho0,
                          double modulus_upper, double confidence = 0.95);

double density_law(double density, double k, double n, double rho0, double modulus_upper);

// Paper: rho = (1 - porosity) / (w_p/rho_p + w_b/rho_b), w = mass fractions.
double mixture_density(double porosity, double mass_fraction_grain, double rho_grain, double rho_binder);

}  // namespace pbx
