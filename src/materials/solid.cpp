// Deck reading common to every composed material: its keys and its thermal setup. The strict check
// of unknown keys (so the point driver, which reads only one table of a run deck, still rejects
// typos) is make_solid's, in models.hpp.
#include "materials/solid.hpp"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "core/error.hpp"
#include "materials/linear_bulk.hpp"
#include "materials/mie_gruneisen.hpp"
#include "materials/tait.hpp"
#include "core/param_table.hpp"
#include "materials/elastic_deviator.hpp"
#include "materials/j2_deviator.hpp"
#include "materials/models.hpp"
#include "materials/prony_deviator.hpp"

namespace pbx {

std::vector<std::string> solid_common_keys() {
  return {"model", "density", "reference_temperature", "thermal_expansion"};
}

SolidSetup read_solid_setup(const ParamTable& t, const MaterialContext& ctx) {
  SolidSetup s;
  s.name = ctx.name.empty() ? t.path() : ctx.name;
  s.temperature = ctx.temperature;
  if (!(s.temperature > 0.0 && std::isfinite(s.temperature)))
    throw InputError(fmt::format("material '{}': temperature must be > 0 K (got {})", s.name, s.temperature));
  s.reference_temperature = t.positive("reference_temperature", dim::temperature, 293.0);
  const double rho_ref = t.positive("density", dim::density);
  // the densest element is 22,590 kg/m3: far above it is a unit slip (g/cm3 written as kg/m3 x 1000)
  if (rho_ref > 1e5) t.fail("density", fmt::format("{} kg/m3 exceeds 1e5 kg/m3 (100 g/cm3): check the unit", rho_ref));
  const double alpha_v = t.quantity("thermal_expansion", dim::per_temperature, 0.0);
  // The expansion law is meant for tens of kelvin around the reference: a run temperature that
  // changes the density by more than 20 % is a slip (a unit, a sign), not a state to compute.
  const double strain_v = alpha_v * (s.temperature - s.reference_temperature);
  if (std::fabs(strain_v) > 0.2)
    t.fail("thermal_expansion",
           fmt::format("{:.4g} 1/K at {:.6g} K (reference {:.6g} K) changes the density by {:.3g} %: "
                       "beyond the thermal expansion this model is for (at most 20 %)",
                       alpha_v, s.temperature, s.reference_temperature, 100 * (std::exp(-strain_v) - 1)));
  s.density = rho_ref * std::exp(-strain_v);
  return s;
}

}  // namespace pbx
