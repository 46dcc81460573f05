#include "materials/tait.hpp"

#include <fmt/format.h>

#include "core/param_table.hpp"

namespace pbx {

TaitEos TaitEos::from_params(const ParamTable& t, const SolidSetup& s) {
  const double C = t.number("tait_c");
  if (!(C > 0.0)) t.fail("tait_c", fmt::format("must be > 0 (got {})", C));
  const double K0 = t.positive("tait_k0", dim::pressure);
  const double B1 = t.quantity("tait_b1", dim::per_temperature, 0.0);
  return TaitEos(C, k0_at(K0, B1, s.temperature, s.reference_temperature));
}

}  // namespace pbx
