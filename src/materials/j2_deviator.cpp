#include "materials/j2_deviator.hpp"

#include <fmt/format.h>

#include "core/param_table.hpp"

namespace pbx {

J2Deviator J2Deviator::from_params(const ParamTable& t, const SolidSetup&) {
  Params p;
  p.G = t.positive("shear_modulus", dim::pressure);
  p.sigma0 = t.positive("yield_stress", dim::pressure);
  p.Ep = t.non_negative("hardening_modulus", dim::pressure, 0.0);
  p.beta = t.in_range("hardening_beta", 0.0, 1.0, 1.0);
  p.cs_C = t.non_negative("cowper_symonds_c", dim::rate, 0.0);
  p.cs_P = t.number("cowper_symonds_p", 0.0);
  if (p.cs_C > 0.0 && !(p.cs_P > 0.0))
    t.fail("cowper_symonds_p", fmt::format("must be > 0 when cowper_symonds_c > 0 (got {})", p.cs_P));
  if (p.cs_P < 0.0) t.fail("cowper_symonds_p", fmt::format("must be >= 0 (got {})", p.cs_P));
  return J2Deviator(p);
}

}  // namespace pbx
