#include "materials/time_temperature_shift.hpp"

#include <cmath>

#include <fmt/format.h>

#include "core/error.hpp"
#include "core/param_table.hpp"

namespace pbx {

TimeTemperatureShift TimeTemperatureShift::from_params(const ParamTable& t) {
  TimeTemperatureShift s;
  const std::string kind = t.string("shift", "none");
  if (kind == "none") {
    s.kind = Kind::none;
  } else if (kind == "arrhenius") {
    s.kind = Kind::arrhenius;
    s.activation_energy = t.positive("activation_energy", dim::molar_energy);
    // A plain number is J/mol: "100" meant as kJ/mol would give a binder without temperature
    // dependence (a_T(373 K) = 0.99) and no complaint. Polymers' flow: tens to hundreds of kJ/mol.
    if (s.activation_energy < 1e3)
      t.fail("activation_energy",
             fmt::format("{} J/mol is below 1 kJ/mol, far below any polymer's (tens to hundreds of "
                         "kJ/mol; a plain number is J/mol: write e.g. \"100 kJ/mol\"); for no "
                         "temperature shift use shift = \"none\"",
                         s.activation_energy));
  } else if (kind == "wlf") {
    s.kind = Kind::wlf;
    s.c1 = t.number("wlf_c1");
    s.c2 = t.positive("wlf_c2", dim::temperature);
  } else {
    t.fail("shift", fmt::format("unknown shift '{}' (known: none, arrhenius, wlf)", kind));
  }
  return s;
}

double TimeTemperatureShift::factor(double T, double Tref) const {
  switch (kind) {
    case Kind::none:
      return 1.0;
    case Kind::arrhenius:
      return std::exp(activation_energy / gas_constant * (1.0 / T - 1.0 / Tref));
    case Kind::wlf:
      if (!(c2 + T - Tref > 0.0))
        throw InputError(
            fmt::format("WLF shift undefined at T = {} K: wlf_c2 + T - Tref = {} K must be > 0", T, c2 + T - Tref));
      return std::pow(10.0, -c1 * (T - Tref) / (c2 + T - Tref));
  }
  return 1.0;
}

}  // namespace pbx
