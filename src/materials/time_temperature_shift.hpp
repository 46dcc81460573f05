#pragma once
// Time-temperature superposition: relaxation times at temperature T are tau_k a_T.
//   Arrhenius: a_T = exp[(Ea/R) (1/T - 1/Tref)]
//   WLF:       log10 a_T = -C1 (T - Tref) / (C2 + T - Tref)   (requires C2 + T - Tref > 0)
// a_T < 1 above Tref: relaxation is faster, the material softer.
#include <string>
#include <vector>

namespace pbx {

class ParamTable;

struct TimeTemperatureShift {
  enum class Kind { none, arrhenius, wlf };
  Kind kind = Kind::none;
  double activation_energy = 0;  // J/mol (Arrhenius)
  double c1 = 0, c2 = 0;         // WLF, c2 in K

  static constexpr double gas_constant = 8.31446261815324;  // J/(mol K)
  static std::vector<std::string> keys() { return {"shift", "activation_energy", "wlf_c1", "wlf_c2"}; }
  // Reads `shift` ("none", "arrhenius", "wlf") and its constants.
  static TimeTemperatureShift from_params(const ParamTable& t);
  // a_T at T for a series referred to Tref; throws InputError (via `t` if given) when undefined.
  double factor(double T, double Tref) const;
};

}  // namespace pbx
