// Isotropic linear elasticity, hypoelastic: Jaumann rate integrated with the Hughes-Winget
// incremental rotation, sigma_n+1 = R sigma_n R^T + (lambda tr(D) I + 2 G D) dt.
#include <cmath>

#include <fmt/format.h>

#include "core/param_table.hpp"
#include "materials/models.hpp"
#include "materials/objective_rotation.hpp"

namespace pbx {

namespace {
template <int D>
class LinearElastic final : public Material<D> {
 public:
  LinearElastic(double rho, double K, double G) : rho_(rho), K_(K), G_(G) {}
  std::string model() const override { return "linear_elastic"; }
  double density() const override { return rho_; }
  double initial_wave_speed() const override { return std::sqrt((K_ + 4.0 * G_ / 3.0) / rho_); }

  MaterialStepResult update(const MaterialBatch<D>& b) const override {
    MaterialStepResult r;
    const double lambda = K_ - 2.0 * G_ / 3.0, M = K_ + 4.0 * G_ / 3.0;
    double work = 0, cmax2 = 0;
    if constexpr (D == 2) return update_plane_strain(b);
    for (std::size_t k = 0; k < b.index.size(); ++k) {
      const auto p = b.index[k];
      const StepRotation<D> R(b.L[p], b.dt);
      const Sym3 Ddt = strain_increment<D>(b.L[p], b.dt);
      const Sym3 s0 = b.stress[p];
      Sym3 s = R.apply(s0);
      s += Sym3::identity(lambda * Ddt.trace()) + (2.0 * G_) * Ddt;
      b.stress[p] = s;
      work += stress_work(s0, s, Ddt, b.volume[p]);
      const double c2 = M * b.volume[p] / b.mass[p];
      cmax2 = std::max(cmax2, c2);
    }
    r.stress_work = work;
    r.max_wave_speed = std::sqrt(cmax2);
    return r;
  }

 private:
  // The same update in plane strain, written out for the components that D dt has (xx, yy, xy;
  // its z components are zero): the general form spent a third of its time multiplying and adding
  // those zeros, which the compiler may not drop (0 * x is not 0 for every x). The results are
  // those of the general form to the bit, but for the sign of an exact zero.
  MaterialStepResult update_plane_strain(const MaterialBatch<D>& b) const {
    const double lambda = K_ - 2.0 * G_ / 3.0, M = K_ + 4.0 * G_ / 3.0, two_g = 2.0 * G_, dt = b.dt;
    double work = 0, cmax2 = 0;
    for (std::size_t k = 0; k < b.index.size(); ++k) {
      const auto p = b.index[k];
      const Mat<D>& L = b.L[p];
      const StepRotation<D> R(L, dt);
      const double dxx = L(0, 0) * dt, dyy = L(1, 1) * dt, dxy = 0.5 * (L(0, 1) + L(1, 0)) * dt;
      const Sym3 s0 = b.stress[p];
      Sym3 s = R.apply(s0);
      const double lt = lambda * (dxx + dyy);
      s.xx += lt + two_g * dxx;
      s.yy += lt + two_g * dyy;
      s.zz += lt;
      s.xy += two_g * dxy;
      b.stress[p] = s;
      // stress_work(s0, s, D dt, V) with the zero components left out
      work += 0.5 * b.volume[p] * ((s0.xx + s.xx) * dxx + (s0.yy + s.yy) * dyy + 2.0 * ((s0.xy + s.xy) * dxy));
      cmax2 = std::max(cmax2, M * b.volume[p] / b.mass[p]);
    }
    MaterialStepResult r;
    r.stress_work = work;
    r.max_wave_speed = std::sqrt(cmax2);
    return r;
  }

  double rho_, K_, G_;
};
}  // namespace

template <int D>
std::unique_ptr<Material<D>> make_linear_elastic(const ParamTable& t, const MaterialContext&) {
  const double rho = t.positive("density", dim::density);
  // the densest element is 22,590 kg/m3: far above it is a unit slip (g/cm3 written as kg/m3 x 1000)
  if (rho > 1e5) t.fail("density", fmt::format("{} kg/m3 exceeds 1e5 kg/m3 (100 g/cm3): check the unit", rho));
  double K, G;
  const bool en = t.has("youngs_modulus") || t.has("poisson_ratio"),
             kg = t.has("bulk_modulus") || t.has("shear_modulus");
  // two definitions of one elasticity: neither may be ignored (it was reported as an unknown key)
  if (en && kg)
    t.fail(t.has("bulk_modulus") ? "bulk_modulus" : "shear_modulus",
           "give bulk_modulus and shear_modulus, or youngs_modulus and poisson_ratio, not both pairs");
  if (en) {
    const double E = t.positive("youngs_modulus", dim::pressure);
    const double nu = t.number("poisson_ratio");
    if (!(nu > -1.0 && nu < 0.5)) t.fail("poisson_ratio", "must lie in (-1, 0.5)");
    K = E / (3.0 * (1.0 - 2.0 * nu));
    G = E / (2.0 * (1.0 + nu));
  } else {
    K = t.positive("bulk_modulus", dim::pressure);
    G = t.positive("shear_modulus", dim::pressure);
  }
  return std::make_unique<LinearElastic<D>>(rho, K, G);
}

template std::unique_ptr<Material<2>> make_linear_elastic<2>(const ParamTable&, const MaterialContext&);
template std::unique_ptr<Material<3>> make_linear_elastic<3>(const ParamTable&, const MaterialContext&);

}  // namespace pbx
