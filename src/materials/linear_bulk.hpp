#pragma once
// Linear bulk EOS, p = -K ln J: the exact integral of the hypoelastic rate dp = -K tr(D) dt, so a
// material built from it matches `linear_elastic` step for step. Stateless.
#include <cmath>
#include <string>
#include <vector>

#include "materials/solid_setup.hpp"

namespace pbx {

class ParamTable;

class LinearBulkEos {
 public:
  static constexpr const char* name = "linear";
  static std::vector<std::string> keys() { return {"bulk_modulus"}; }
  static LinearBulkEos from_params(const ParamTable& t, const SolidSetup& s);
  explicit LinearBulkEos(double K) : K_(K) {}

  int history_size() const { return 0; }
  std::vector<std::string> history_names() const { return {}; }
  void init_history(double*) const {}
  double initial_bulk_modulus() const { return K_; }
  double pressure(double J) const { return -K_ * std::log(J); }
  EosResult update(double J, double /*heat*/, double* /*h*/) const { return {pressure(J), K_}; }

 private:
  double K_;
};

}  // namespace pbx
