#include "materials/prony_deviator.hpp"

#include <fmt/format.h>

#include "core/param_table.hpp"

namespace pbx {

std::vector<std::string> PronyDeviator::keys() {
  auto k = TimeTemperatureShift::keys();
  for (const char* s :
       {"long_term_shear_modulus", "prony_shear_moduli", "prony_shear_times", "prony_bulk_moduli", "prony_bulk_times"})
    k.push_back(s);
  return k;
}

namespace {
void read_series(const ParamTable& t, const std::string& mkey, const std::string& tkey, std::vector<double>& m,
                 std::vector<double>& tau) {
  m = t.quantities(mkey, dim::pressure);
  tau = t.quantities(tkey, dim::time);
  if (m.size() != tau.size()) t.fail(tkey, fmt::format("has {} entries but {} has {}", tau.size(), mkey, m.size()));
  for (double v : m)
    if (!(v > 0.0)) t.fail(mkey, fmt::format("every modulus must be > 0 (got {} Pa)", v));
  for (double v : tau)
    if (!(v > 0.0)) t.fail(tkey, fmt::format("every relaxation time must be > 0 (got {} s)", v));
}
}  // namespace

PronyDeviator PronyDeviator::from_params(const ParamTable& t, const SolidSetup& s) {
  Params p;
  p.G_inf = t.non_negative("long_term_shear_modulus", dim::pressure);
  read_series(t, "prony_shear_moduli", "prony_shear_times", p.G, p.tau);
  if (p.G.empty()) t.fail("prony_shear_moduli", "must list at least one Prony term");
  if (t.has("prony_bulk_moduli") || t.has("prony_bulk_times"))
    read_series(t, "prony_bulk_moduli", "prony_bulk_times", p.K, p.tauK);
  p.shift = TimeTemperatureShift::from_params(t);
  double aT = 0.0;  // set below, or t.fail throws
  try {
    aT = p.shift.factor(s.temperature, s.reference_temperature);
  } catch (const std::exception& e) {
    t.fail("shift", e.what());
  }
  if (!(aT > 0.0 && std::isfinite(aT)))
    t.fail("shift", fmt::format("shift factor a_T = {} at {} K is not a positive finite number", aT, s.temperature));
  return PronyDeviator(p, aT);
}

PronyDeviator::PronyDeviator(const Params& p, double a_T) : p_(p), aT_(a_T), G0_(p.G_inf), K0_(0) {
  for (double g : p_.G) G0_ += g;
  for (double k : p_.K) K0_ += k;
}

double PronyDeviator::shear_relaxation(double t) const {
  double g = p_.G_inf;
  for (std::size_t k = 0; k < p_.G.size(); ++k) g += p_.G[k] * std::exp(-t / (p_.tau[k] * aT_));
  return g;
}

double PronyDeviator::bulk_overstress_relaxation(double t) const {
  double g = 0;
  for (std::size_t k = 0; k < p_.K.size(); ++k) g += p_.K[k] * std::exp(-t / (p_.tauK[k] * aT_));
  return g;
}

PronyDeviator::Branch PronyDeviator::branch(double m2, double x) {
  Branch b;
  const double q = -std::expm1(-x);  // 1 - e^-x, accurate for small x
  b.a = 1.0 - q;
  if (x < 1e-3) {
    // Series of (1 - e^-x)/x, (1 - e^-x)^2/x and (x - q - q^2/2)/x^2 (the last cancels badly).
    b.b = m2 * (1.0 - 0.5 * x + x * x / 6.0);
    b.c2 = x * (1.0 - x + 7.0 / 12.0 * x * x);
    b.c3 = m2 * x * (1.0 / 3.0 - 0.25 * x + 7.0 / 60.0 * x * x);
  } else {
    b.b = m2 * q / x;
    b.c2 = q * q / x;
    b.c3 = m2 * (x - q - 0.5 * q * q) / (x * x);
  }
  b.c1 = -std::expm1(-2.0 * x) / (2.0 * m2);
  return b;
}

PronyDeviator::Step PronyDeviator::prepare(double dt) const {
  Step st;
  st.shear.reserve(p_.G.size());
  for (std::size_t k = 0; k < p_.G.size(); ++k) st.shear.push_back(branch(2.0 * p_.G[k], dt / (p_.tau[k] * aT_)));
  for (std::size_t j = 0; j < p_.K.size(); ++j) st.bulk.push_back(branch(p_.K[j], dt / (p_.tauK[j] * aT_)));
  return st;
}

}  // namespace pbx
