#include "materials/mie_gruneisen.hpp"

#include <fmt/format.h>

#include "core/error.hpp"
#include "core/param_table.hpp"

namespace pbx {

std::vector<std::string> MieGruneisenEos::keys() {
  return {"sound_speed",      "hugoniot_s1", "hugoniot_s2",          "hugoniot_s3",
          "gruneisen_gamma0", "gruneisen_a", "dissipation_to_energy"};
}

MieGruneisenEos MieGruneisenEos::from_params(const ParamTable& t, const SolidSetup& s) {
  Params p;
  p.rho0 = s.density;
  p.c = t.positive("sound_speed", dim::velocity);
  p.s1 = t.number("hugoniot_s1");
  if (!(p.s1 > 1.0)) t.fail("hugoniot_s1", fmt::format("must be > 1 (got {})", p.s1));
  p.s2 = t.number("hugoniot_s2", 0.0);
  p.s3 = t.number("hugoniot_s3", 0.0);
  p.gamma0 = t.number("gruneisen_gamma0");
  if (!(p.gamma0 >= 0.0)) t.fail("gruneisen_gamma0", fmt::format("must be >= 0 (got {})", p.gamma0));
  p.a = t.number("gruneisen_a", 0.0);
  p.dissipation_to_energy = t.boolean("dissipation_to_energy", true);
  return MieGruneisenEos(p, s.name);
}

MieGruneisenEos::MieGruneisenEos(const Params& p, std::string material)
    : p_(p), rho0c2_(p.rho0 * p.c * p.c), material_(std::move(material)) {}

void MieGruneisenEos::beyond_fit(double mu) const {
  throw InstabilityError(
      fmt::format("material '{}': Mie-Grueneisen compression mu = {:.4g} is beyond the limit of the Hugoniot fit "
                  "(denominator <= 0)",
                  material_, mu));
}

std::string MieGruneisenEos::failure_reason(double J) const {
  if (!(J > 0.0)) return {};
  const double mu = 1.0 / J - 1.0;
  double A, dA;
  cold_with_slope(mu, J, A, dA);
  if (!std::isnan(A)) return {};
  return fmt::format(
      "compression mu = rho/rho0 - 1 = {:.4g} beyond the limit of the Mie-Grueneisen Hugoniot fit "
      "(denominator <= 0; for s2 = s3 = 0 at mu = 1/(s1 - 1) = {:.4g})",
      mu, 1.0 / (p_.s1 - 1.0));
}

}  // namespace pbx
