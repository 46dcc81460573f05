#pragma once
// Generalized Maxwell viscoelasticity (paper Eq. 10): G(t) = G_inf + sum_k G_k exp(-t/tau_k'),
// optionally K(t) = K_eos + sum_j K_j exp(-t/tauK_j'), tau' = tau a_T (time-temperature shift).
// Each Maxwell branch carries its own stress h_k, updated exactly for a strain rate that is constant
// over the step (x = dt/tau'):
//   h_k,n+1 = e^-x R h_k,n R^T + 2 G_k (1 - e^-x)/x de,   s = R s_n R^T + 2 G_inf de + sum (h_n+1 - R h_n R^T)
// so the total deviator itself carries the G_inf part. Bulk branches are scalars on dtheta = tr(D) dt
// and add an isotropic overstress sum_j hK_j on top of the EOS pressure.
// Dissipation in a branch over the step is integrated exactly for the same constant rate:
//   int h:h/(2 G tau') dt = c1 |h_n|^2 + c2 h_n:de + c3 |de|^2,
//   c1 = (1 - e^-2x)/(4G), c2 = (1 - e^-x)^2/x, c3 = 2G (x - q - q^2/2)/x^2, q = 1 - e^-x.
// The per-branch factors depend on dt and T only: computed once per update call (prepare).
#include <cmath>
#include <string>
#include <vector>

#include "materials/deviatoric_storage.hpp"
#include "materials/objective_rotation.hpp"
#include "materials/solid_setup.hpp"
#include "materials/time_temperature_shift.hpp"

namespace pbx {

class ParamTable;

class PronyDeviator {
 public:
  struct Params {
    double G_inf = 0;             // Pa
    std::vector<double> G, tau;   // shear branches: Pa, s (at the reference temperature)
    std::vector<double> K, tauK;  // bulk branches: Pa, s
    TimeTemperatureShift shift;
  };
  static constexpr const char* name = "viscoelastic";
  static std::vector<std::string> keys();
  static PronyDeviator from_params(const ParamTable& t, const SolidSetup& s);
  // a_T: shift factor at the run temperature (relaxation times are tau a_T).
  PronyDeviator(const Params& p, double a_T);
  const Params& params() const { return p_; }
  double shift_factor() const { return aT_; }
  // Relaxation moduli at time t (run temperature), Pa.
  double shear_relaxation(double t) const;
  double bulk_overstress_relaxation(double t) const;

  struct Branch {
    double a, b, c1, c2, c3;  // decay, increment gain, dissipation coefficients
  };
  struct Step {
    std::vector<Branch> shear, bulk;
  };
  Step prepare(double dt) const;

  template <int D>
  int history_size() const {
    return static_cast<int>(p_.G.size()) * DeviatoricStorage<D>::size + static_cast<int>(p_.K.size());
  }
  template <int D>
  std::vector<std::string> history_names() const {
    std::vector<std::string> n;
    for (std::size_t k = 0; k < p_.G.size(); ++k)
      DeviatoricStorage<D>::names("prony_shear" + std::to_string(k + 1) + "_Pa", n);
    for (std::size_t j = 0; j < p_.K.size(); ++j) n.push_back("prony_bulk" + std::to_string(j + 1) + "_Pa");
    return n;
  }
  template <int D>
  void init_history(double* h) const {
    for (int i = 0; i < history_size<D>(); ++i) h[i] = 0.0;
  }
  double plastic_strain(const double*) const { return 0.0; }
  double shear_modulus() const { return G0_; }            // instantaneous G(0)
  double bulk_overstress_modulus() const { return K0_; }  // instantaneous sum K_j

  template <int D>
  Sym3 update(const Step& st, const Sym3& s_rot, const StepRotation<D>& R, const Sym3& de, double dtheta, double* h,
              double& diss) const {
    constexpr int n = DeviatoricStorage<D>::size;
    Sym3 s = s_rot + (2.0 * p_.G_inf) * de;
    const double de2 = de.ddot(de);
    double d = 0;
    const std::size_t ns = st.shear.size();
    if constexpr (D == 2) {
      // (m, d, xy) storage of deviatoric_storage.hpp: rotation turns (d, xy) by 2 theta only.
      const double em = 0.5 * (de.xx + de.yy), ed = 0.5 * (de.xx - de.yy), exy = de.xy;
      double sm = 0, sd = 0, sxy = 0;
      for (std::size_t k = 0; k < ns; ++k) {
        const Branch& br = st.shear[k];
        double* hk = h + k * n;
        const double m0 = hk[0];
        const double d0 = R.c2 * hk[1] + R.s2 * hk[2];
        const double x0 = R.c2 * hk[2] - R.s2 * hk[1];
        const double m1 = br.a * m0 + br.b * em, d1 = br.a * d0 + br.b * ed, x1 = br.a * x0 + br.b * exy;
        d += br.c1 * (6.0 * m0 * m0 + 2.0 * (d0 * d0 + x0 * x0)) +
             br.c2 * (6.0 * m0 * em + 2.0 * (d0 * ed + x0 * exy)) + br.c3 * de2;
        sm += m1 - m0, sd += d1 - d0, sxy += x1 - x0;
        hk[0] = m1, hk[1] = d1, hk[2] = x1;
      }
      s += Sym3{sm + sd, sm - sd, -2.0 * sm, sxy, 0.0, 0.0};
    } else {
      for (std::size_t k = 0; k < ns; ++k) {
        const Branch& br = st.shear[k];
        double* hk = h + k * n;
        const Sym3 h0 = R.apply(DeviatoricStorage<D>::load(hk));
        const Sym3 h1 = br.a * h0 + br.b * de;
        d += br.c1 * h0.ddot(h0) + br.c2 * h0.ddot(de) + br.c3 * de2;
        s += h1 - h0;
        DeviatoricStorage<D>::store(h1, hk);
      }
    }
    if (!st.bulk.empty()) {
      double* hb = h + ns * n;
      double m = 0;
      for (std::size_t j = 0; j < st.bulk.size(); ++j) {
        const Branch& br = st.bulk[j];
        const double h0 = hb[j], h1 = br.a * h0 + br.b * dtheta;
        d += br.c1 * h0 * h0 + br.c2 * h0 * dtheta + br.c3 * dtheta * dtheta;
        hb[j] = h1;
        m += h1;
      }
      s += Sym3::identity(m);
    }
    diss += d;
    return s;
  }

 private:
  static Branch branch(double modulus2, double x);  // modulus2 = 2G (shear) or K (bulk)
  Params p_;
  double aT_, G0_, K0_;
};

}  // namespace pbx
