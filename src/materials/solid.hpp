#pragma once
// A material as a composition (DESIGN.md): a deviatoric law (ElasticDeviator, J2Deviator,
// PronyDeviator) and an equation of state (LinearBulkEos, MieGruneisenEos, TaitEos) combined at
// compile time in one batch loop, so there is no virtual call per particle.
// Per particle and step:
//   1. D dt and the Hughes-Winget rotation R from L (objective_rotation.hpp);
//   2. s = deviator law (R dev(sigma_n) R^T, dev(D dt), tr(D dt), history);
//   3. p = EOS(J = V/V_ref, dissipated energy per reference volume);
//   4. sigma = s - p I.
// History layout per particle: the deviator's variables, then the EOS's.
#include <algorithm>
#include <cmath>
#include <string>
#include <utility>

#include "materials/material.hpp"
#include "materials/objective_rotation.hpp"
#include "materials/solid_setup.hpp"

namespace pbx {

template <int D, class Dev, class Eos>
class Solid final : public Material<D> {
 public:
  Solid(const SolidSetup& s, Dev dev, Eos eos)
      : setup_(s),
        dev_(std::move(dev)),
        eos_(std::move(eos)),
        nd_(dev_.template history_size<D>()),
        nh_(nd_ + eos_.history_size()) {}

  static std::string model_name() { return std::string(Dev::name) + "_" + Eos::name; }
  std::string model() const override { return model_name(); }
  double density() const override { return setup_.density; }
  double initial_wave_speed() const override { return std::sqrt(initial_longitudinal_modulus() / setup_.density); }
  // M = K + 4G/3 of the unstressed material (instantaneous moduli), Pa.
  double initial_longitudinal_modulus() const {
    return eos_.initial_bulk_modulus() + dev_.bulk_overstress_modulus() + 4.0 / 3.0 * dev_.shear_modulus();
  }
  int history_size() const override { return nh_; }
  std::vector<std::string> history_names() const override {
    auto n = dev_.template history_names<D>();
    for (auto& e : eos_.history_names()) n.push_back(e);
    return n;
  }
  void init_history(double* h) const override {
    dev_.template init_history<D>(h);
    eos_.init_history(h + nd_);
  }
  double plastic_strain(const double* h) const override { return dev_.plastic_strain(h); }
  std::string failure_reason(double J) const override {
    if constexpr (requires { eos_.failure_reason(J); })
      return eos_.failure_reason(J);
    else
      return {};
  }
  const Dev& deviator() const { return dev_; }
  const Eos& eos() const { return eos_; }
  const SolidSetup& setup() const { return setup_; }

  MaterialStepResult update(const MaterialBatch<D>& b) const override {
    const auto st = dev_.prepare(b.dt);
    const double M_dev = dev_.bulk_overstress_modulus() + 4.0 / 3.0 * dev_.shear_modulus();
    double work = 0, diss = 0, cmax2 = 0;
    const std::size_t n = b.index.size();
    for (std::size_t k = 0; k < n; ++k) {
      const auto p = b.index[k];
      const Mat<D>& L = b.L[p];
      const StepRotation<D> R(L, b.dt);
      const Sym3 Ddt = strain_increment<D>(L, b.dt);
      const Sym3 de = Ddt.dev();
      const Sym3 sig0 = b.stress[p];
      double* h = b.history + k * static_cast<std::size_t>(nh_);
      double dd = 0;  // dissipated energy per unit current volume
      Sym3 s = dev_.template update<D>(st, R.apply(sig0.dev()), R, de, Ddt.trace(), h, dd);
      const double V = b.volume[p], J = V / b.volume0[p];
      const EosResult e = eos_.update(J, dd * J, h + nd_);
      s += Sym3::identity(-e.pressure);
      b.stress[p] = s;
      work += stress_work(sig0, s, Ddt, V);
      diss += dd * V;
      cmax2 = std::max(cmax2, (e.bulk_modulus + M_dev) * V / b.mass[p]);
    }
    MaterialStepResult r;
    r.stress_work = work;
    r.dissipated = diss;
    r.max_wave_speed = std::sqrt(cmax2);
    return r;
  }

 private:
  SolidSetup setup_;
  Dev dev_;
  Eos eos_;
  int nd_, nh_;
};

}  // namespace pbx
