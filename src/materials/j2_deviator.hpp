#pragma once
// J2 elastic-plastic deviator with Cowper-Symonds rate factor and mixed hardening (paper Eq. 8,
// LS-DYNA *MAT_PLASTIC_KINEMATIC form):
//   sigma_y = [1 + (epsdot/C)^(1/P)] (sigma0 + beta Ep eps_p),  back stress modulus (1 - beta) Ep.
// C = 0 switches the rate term off (never divides by zero). epsdot is the von Mises equivalent of
// the deviatoric strain rate, sqrt(2/3 dev(D):dev(D)).
// Radial return in 3D deviatoric space (plane strain keeps sigma_zz): with xi = s_tr - alpha,
// q = sqrt(3/2 xi:xi), f = q - sigma_y(eps_p); if f > 0
//   d_eps_p = f / (3G + (1 - beta) Ep + R_f beta Ep),   s = s_tr - 3G d_eps_p xi/q,
//   alpha += (1 - beta) Ep d_eps_p xi/q.
// Dissipation (s_n+1 - alpha_n+1) : d_eps_plastic is returned: the plastic work less the part
// stored in the back stress.
#include <cmath>
#include <string>
#include <vector>

#include "materials/deviatoric_storage.hpp"
#include "materials/objective_rotation.hpp"
#include "materials/solid_setup.hpp"

namespace pbx {

class ParamTable;

class J2Deviator {
 public:
  struct Params {
    double G = 0;       // shear modulus, Pa
    double sigma0 = 0;  // initial yield stress, Pa
    double Ep = 0;      // plastic hardening modulus, Pa
    double beta = 1;    // 1 isotropic, 0 kinematic
    double cs_C = 0;    // Cowper-Symonds C, 1/s (0 = off)
    double cs_P = 0;    // Cowper-Symonds P
  };
  static constexpr const char* name = "j2";
  static std::vector<std::string> keys() {
    return {"shear_modulus",  "yield_stress",     "hardening_modulus",
            "hardening_beta", "cowper_symonds_c", "cowper_symonds_p"};
  }
  static J2Deviator from_params(const ParamTable& t, const SolidSetup& s);
  explicit J2Deviator(const Params& p) : p_(p), kinematic_(p.beta < 1.0 && p.Ep > 0.0) {}
  const Params& params() const { return p_; }

  // Cowper-Symonds factor at equivalent strain rate `rate` (1/s).
  double rate_factor(double rate) const { return p_.cs_C > 0.0 ? 1.0 + std::pow(rate / p_.cs_C, 1.0 / p_.cs_P) : 1.0; }

  struct Step {
    double inv_dt;
  };
  Step prepare(double dt) const { return {dt > 0 ? 1.0 / dt : 0.0}; }
  template <int D>
  int history_size() const {
    return 1 + (kinematic_ ? DeviatoricStorage<D>::size : 0);
  }
  template <int D>
  std::vector<std::string> history_names() const {
    std::vector<std::string> n{"plastic_strain"};
    if (kinematic_) DeviatoricStorage<D>::names("back_stress_Pa", n);
    return n;
  }
  template <int D>
  void init_history(double* h) const {
    for (int i = 0; i < history_size<D>(); ++i) h[i] = 0.0;
  }
  double plastic_strain(const double* h) const { return h[0]; }
  double shear_modulus() const { return p_.G; }
  double bulk_overstress_modulus() const { return 0.0; }

  template <int D>
  Sym3 update(const Step& st, const Sym3& s_rot, const StepRotation<D>& R, const Sym3& de, double /*dtheta*/, double* h,
              double& diss) const {
    const double twoG = 2.0 * p_.G;
    Sym3 s = s_rot + twoG * de;
    Sym3 alpha;
    if (kinematic_) alpha = R.apply(DeviatoricStorage<D>::load(h + 1));
    const Sym3 xi = kinematic_ ? s - alpha : s;
    const double q = std::sqrt(1.5 * xi.ddot(xi));
    double Rf = 1.0;
    if (p_.cs_C > 0.0) Rf = rate_factor(std::sqrt(2.0 / 3.0 * de.ddot(de)) * st.inv_dt);
    const double sy = Rf * (p_.sigma0 + p_.beta * p_.Ep * h[0]);
    if (q > sy) {
      const double dp = (q - sy) / (3.0 * p_.G + (1.0 - p_.beta) * p_.Ep + Rf * p_.beta * p_.Ep);
      const double f = dp / q;
      s += (-3.0 * p_.G * f) * xi;
      h[0] += dp;
      if (kinematic_) {
        alpha += ((1.0 - p_.beta) * p_.Ep * f) * xi;
        DeviatoricStorage<D>::store(alpha, h + 1);
        // alpha : d eps_p is stored in the back stress (given back on reverse loading), not heat
        diss += 1.5 * f * (s - alpha).ddot(xi);
      } else {
        diss += 1.5 * f * s.ddot(xi);
      }
    } else if (kinematic_) {
      DeviatoricStorage<D>::store(alpha, h + 1);
    }
    return s;
  }

 private:
  Params p_;
  bool kinematic_;
};

}  // namespace pbx
