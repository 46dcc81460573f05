#pragma once
// Mie-Grueneisen EOS in the LS-DYNA *EOS_GRUNEISEN form (paper Eq. 9 with its typos fixed:
// rho0 in front, the denominator squared, S3 mu^3/(mu+1)^2). mu = rho/rho0 - 1 = 1/J - 1.
//   compression (mu > 0): p = rho0 c^2 mu [1 + (1 - g0/2) mu - (a/2) mu^2]
//                               / [1 - (S1 - 1) mu - S2 mu^2/(mu+1) - S3 mu^3/(mu+1)^2]^2 + (g0 + a mu) E
//   expansion (mu <= 0):   p = rho0 c^2 mu + (g0 + a mu) E
// E is the internal energy per unit reference volume. Over a step it is updated with the
// trapezoidal pressure work, which is implicit in E because p is linear in E:
//   E1 = [E0 - (p0 + A1) dJ/2 + heat] / [1 + B1 dJ/2],  dJ = J1 - J0,  p1 = A1 + B1 E1,
// with A = cold part, B = g0 + a mu. History per particle: E, J and p at the end of the last step.
#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "materials/solid_setup.hpp"

namespace pbx {

class ParamTable;

class MieGruneisenEos {
 public:
  struct Params {
    double rho0 = 0;  // kg/m^3 (stress-free density at the run temperature)
    double c = 0;     // m/s, bulk sound speed (Us intercept)
    double s1 = 0, s2 = 0, s3 = 0;
    double gamma0 = 0;                  // Grueneisen gamma
    double a = 0;                       // first-order volume correction of gamma
    bool dissipation_to_energy = true;  // add the deviatoric law's dissipation to E
  };
  static constexpr const char* name = "mie_gruneisen";
  static std::vector<std::string> keys();
  static MieGruneisenEos from_params(const ParamTable& t, const SolidSetup& s);
  MieGruneisenEos(const Params& p, std::string material);

  int history_size() const { return 3; }
  std::vector<std::string> history_names() const { return {"eos_energy_J_m3", "eos_volume_ratio", "eos_pressure_Pa"}; }
  void init_history(double* h) const { h[0] = 0.0, h[1] = 1.0, h[2] = 0.0; }
  double initial_bulk_modulus() const { return rho0c2_; }
  const Params& params() const { return p_; }

  // Cold (E = 0) pressure A(mu) and its slope dA/dmu. Throws InstabilityError past the limit of
  // the Hugoniot fit (denominator <= 0, mu >= 1/(S1 - 1) for S2 = S3 = 0).
  double cold(double mu) const {
    double A, dA;
    cold_with_slope(mu, A, dA);
    if (std::isnan(A)) beyond_fit(mu);
    return A;
  }
  double cold_slope(double mu) const {
    double A, dA;
    cold_with_slope(mu, A, dA);
    return dA;
  }
  void cold_with_slope(double mu, double& A, double& dA) const { cold_with_slope(mu, 1.0 / (1.0 + mu), A, dA); }
  // The same with r = 1/(1 + mu) = J supplied, which saves the stress update a division. Past the
  // limit of the fit A and dA are NaN, not an exception: the stress update runs inside OpenMP
  // regions, which an exception may not leave; the solver's non-finite-stress check stops the run
  // naming the particle, and failure_reason() says why.
  void cold_with_slope(double mu, double r, double& A, double& dA) const {
    if (mu <= 0.0) {
      A = rho0c2_ * mu, dA = rho0c2_;
      return;
    }
    const double num = rho0c2_ * mu * (1.0 + (1.0 - 0.5 * p_.gamma0) * mu - 0.5 * p_.a * mu * mu);
    const double dnum = rho0c2_ * (1.0 + (2.0 - p_.gamma0) * mu - 1.5 * p_.a * mu * mu);
    const double den = 1.0 - (p_.s1 - 1.0) * mu - p_.s2 * mu * mu * r - p_.s3 * mu * mu * mu * r * r;
    if (!(den > 0.0)) {
      A = dA = std::numeric_limits<double>::quiet_NaN();
      return;
    }
    const double dden = -(p_.s1 - 1.0) - p_.s2 * mu * (2.0 + mu) * r * r - p_.s3 * mu * mu * (3.0 + mu) * r * r * r;
    const double id = 1.0 / den, id2 = id * id;
    A = num * id2;
    dA = dnum * id2 - 2.0 * num * dden * id2 * id;
  }
  double gamma(double mu) const { return p_.gamma0 + p_.a * mu; }
  // Why no finite pressure exists at volume ratio J (empty when one does).
  std::string failure_reason(double J) const;
  double pressure(double mu, double E) const { return cold(mu) + gamma(mu) * E; }

  // Advances the particle's EOS state to volume ratio J (relative to the stress-free state at the
  // run temperature); `heat` is dissipated energy per unit reference volume added this step.
  EosResult update(double J, double heat, double* h) const {
    const double opm = 1.0 / J, mu = opm - 1.0;
    const double dJ = J - h[1];
    double A, dA;
    cold_with_slope(mu, J, A, dA);
    const double B = gamma(mu);
    const double add = p_.dissipation_to_energy ? heat : 0.0;
    const double E = (h[0] - 0.5 * (h[2] + A) * dJ + add) / (1.0 + 0.5 * B * dJ);
    const double p = A + B * E;
    h[0] = E, h[1] = J, h[2] = p;
    // Isentropic tangent: K = rho dp/drho = (1 + mu) [A' + a E + B p/(1 + mu)^2].
    const double K = opm * (dA + p_.a * E) + B * p * J;
    return {p, K > 0 ? K : rho0c2_};
  }

 private:
  [[noreturn]] void beyond_fit(double mu) const;
  Params p_;
  double rho0c2_;
  std::string material_;
};

}  // namespace pbx
