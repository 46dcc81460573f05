#pragma once
// Elastic moduli from confined (uniaxial-strain) compression in plane strain: the die walls fix
// e_xx = 0, plane strain fixes e_zz = 0, the punch gives e_yy = e. For an isotropic elastic solid
//   sigma_yy = M e,  M = K + 4G/3 ;  sigma_xx = sigma_zz = lambda e,  lambda = K - 2G/3,
// so G = (M - lambda)/2, K = (M + lambda_x + lambda_z)/3, E = 9KG/(3K + G), nu = (3K - 2G)/(2(3K + G)).
#include "io/json.hpp"
#include "analysis/least_squares.hpp"
#include "analysis/stress_strain_curve.hpp"

namespace pbx {

struct ConfinedModuli {
  // Slopes (Pa) over the linear window; all compression positive.
  LineFit punch;        // M from the punch stress (primary)
  LineFit wall;         // lambda from the side-wall stress (primary)
  LineFit axial_vol;    // M from -<sigma_yy> (cross-check)
  LineFit lateral_vol;  // lambda from -<sigma_xx> (cross-check)
  LineFit zz_vol;       // lambda_z from -<sigma_zz>
  double M = 0, lambda = 0, lambda_z = 0;
  double K = 0;            // (M + lambda + lambda_z)/3, measured sigma_zz
  double K_isotropic = 0;  // (M + 2 lambda)/3, assuming sigma_zz = sigma_xx
  double K_volume = 0;     // from the volume averages alone: slope of -(sxx + syy + szz)/3
  double G = 0, E = 0, nu = 0;
  double lateral_coefficient = 0;  // k0 = lambda / M
  Json to_json() const;
};

// Primary: M from the punch, lambda from the side walls, lambda_z from the volume average.
ConfinedModuli confined_moduli(const StressStrainCurve& c, double lo, double hi);
// The same from the volume averages alone (-<syy> for M, -<sxx> for lambda): the cross-check, and
// the better estimate when stress waves make the punch reaction ring.
ConfinedModuli confined_moduli_volume_average(const StressStrainCurve& c, double lo, double hi);

}  // namespace pbx
