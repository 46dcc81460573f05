#pragma once
// Paper Eq. 12, 14 and 15: the normalised stress-strain curve sigma_n = sigma/sigma_c =
// A e + B e^n with e the strain in PERCENT (the paper's constants only reach sigma_n ~ 1 that way),
// and the combined law sigma = sigma_c(T) (A e + B e^n).
#include <vector>

#include "analysis/least_squares.hpp"

namespace pbx {

// Fits A, B, n (all dimensionless, e in percent) to (strain_percent, sigma_n) with strain_percent > 0.
// Start values: n scanned over (0, 1.5] with A, B by linear least squares at each n (the model is
// linear in A and B), then Levenberg-Marquardt on all three.
FitResult fit_normalized_curve(const std::vector<double>& strain_percent, const std::vector<double>& sigma_n,
                               double confidence = 0.95);

double normalized_curve(double strain_percent, double A, double B, double n);

// Eq. 15: stress (Pa) at strain (fraction, converted to percent inside) and temperature.
double constitutive_stress(double strain, double T_K, double sigma0_Pa, double alpha, double T0_K, double A, double B,
                           double n);

}  // namespace pbx
