#pragma once
// Hypoelastic deviator: s_n+1 = R s_n R^T + 2 G de (de = dev(D) dt).
#include <string>
#include <vector>

#include "materials/objective_rotation.hpp"
#include "materials/solid_setup.hpp"

namespace pbx {

class ParamTable;

class ElasticDeviator {
 public:
  static constexpr const char* name = "elastic";
  static std::vector<std::string> keys() { return {"shear_modulus"}; }
  static ElasticDeviator from_params(const ParamTable& t, const SolidSetup& s);
  explicit ElasticDeviator(double G) : G_(G) {}

  struct Step {};
  Step prepare(double /*dt*/) const { return {}; }
  template <int D>
  int history_size() const {
    return 0;
  }
  template <int D>
  std::vector<std::string> history_names() const {
    return {};
  }
  template <int D>
  void init_history(double*) const {}
  double plastic_strain(const double*) const { return 0.0; }
  double shear_modulus() const { return G_; }  // instantaneous, for the wave speed
  double bulk_overstress_modulus() const { return 0.0; }

  // s_rot: start-of-step deviator already rotated; de: deviatoric strain increment; dtheta: tr(D) dt.
  // Returns the new stress minus the EOS part (deviator, plus any isotropic overstress);
  // adds dissipated energy per unit current volume to `diss`.
  template <int D>
  Sym3 update(const Step&, const Sym3& s_rot, const StepRotation<D>&, const Sym3& de, double /*dtheta*/, double* /*h*/,
              double& /*diss*/) const {
    return s_rot + (2.0 * G_) * de;
  }

 private:
  double G_;
};

}  // namespace pbx
