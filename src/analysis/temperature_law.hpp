#pragma once
// Paper Eq. 13: compression strength against temperature, sigma_c = sigma0 exp(alpha (1 - T/T0)).
#include <vector>

#include "analysis/least_squares.hpp"

namespace pbx {

// Parameters "sigma0" (Pa) and "alpha" (-). Residuals on sigma_c itself (the paper's sigma0 =
// 34.10 MPa matches this fit of its Table 3; see docs/theory/analysis.md).
FitResult fit_temperature_law_nonlinear(const std::vector<double>& T_K, const std::vector<double>& strength_Pa,
                                        double T0_K, double confidence = 0.95);

// Linear least squares of ln sigma_c = ln sigma0 + alpha (1 - T/T0). The interval of sigma0 is
// exp of the interval of ln sigma0 (asymmetric); its std_error is the delta-method sigma0 * SE(ln sigma0).
FitResult fit_temperature_law_loglinear(const std::vector<double>& T_K, const std::vector<double>& strength_Pa,
                                        double T0_K, double confidence = 0.95);

double temperature_law(double T_K, double sigma0, double alpha, double T0_K);

}  // namespace pbx
