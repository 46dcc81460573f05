#pragma once
// Tait EOS for polymers (paper Eq. 11): V/V0(T) = 1 - C ln(1 + p/B(T)), B(T) = C K0(T), inverted
// explicitly for the pressure:  p = B(T) [exp((1 - J)/C) - 1],  J = V/V0(T).
// K0(T) = K0(Tref) exp(-B1 (T - Tref)); V0(T) = V0(Tref) exp(alpha_v (T - Tref)) enters through the
// material's stress-free density rho0(T) = rho0(Tref) exp(-alpha_v (T - Tref)), so the engine's
// J = V/V_ref is already J_T. Stateless.
#include <cmath>
#include <string>
#include <vector>

#include "materials/solid_setup.hpp"

namespace pbx {

class ParamTable;

class TaitEos {
 public:
  static constexpr const char* name = "tait";
  static std::vector<std::string> keys() { return {"tait_c", "tait_k0", "tait_b1"}; }
  static TaitEos from_params(const ParamTable& t, const SolidSetup& s);
  // C: Tait constant; K0: zero-pressure bulk modulus at the run temperature.
  TaitEos(double C, double K0) : C_(C), K0_(K0), B_(C * K0), invC_(1.0 / C) {}

  int history_size() const { return 0; }
  std::vector<std::string> history_names() const { return {}; }
  void init_history(double*) const {}
  double initial_bulk_modulus() const { return K0_; }
  double C() const { return C_; }
  double K0() const { return K0_; }
  double B() const { return B_; }

  double pressure(double J) const { return B_ * std::expm1((1.0 - J) * invC_); }
  // K = -J dp/dJ = J (B/C) exp((1 - J)/C)
  EosResult update(double J, double /*heat*/, double* /*h*/) const {
    const double e = std::exp((1.0 - J) * invC_);
    return {B_ * (e - 1.0), J * K0_ * e};
  }
  // K0(T) from the value at Tref and the slope B1 (1/K).
  static double k0_at(double K0_ref, double B1, double T, double Tref) { return K0_ref * std::exp(-B1 * (T - Tref)); }

 private:
  double C_, K0_, B_, invC_;
};

}  // namespace pbx
