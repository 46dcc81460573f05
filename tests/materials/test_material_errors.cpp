// Bad parameters give an InputError naming the material and the key.
#include <gtest/gtest.h>

#include "core/error.hpp"
#include "material_fixtures.hpp"
#include "materials/point_driver.hpp"

using namespace pbx;

namespace {
std::string error_of(const std::string& body, double T = 293.0) {
  try {
    test::material_from<2>(body, T, "bad");
  } catch (const InputError& e) {
    return e.what();
  }
  return "(no error)";
}
std::string replace(std::string s, const std::string& from, const std::string& to) {
  const auto i = s.find(from);
  EXPECT_NE(i, std::string::npos) << from;
  return s.replace(i, from.size(), to);
}
void expect_error(const std::string& body, const std::string& key, const std::string& what, double T = 293.0) {
  const std::string msg = error_of(body, T);
  EXPECT_NE(msg.find("materials.bad." + key), std::string::npos) << msg;
  EXPECT_NE(msg.find(what), std::string::npos) << msg;
}
}  // namespace

TEST(MaterialErrors, NameTheMaterialAndTheKey) {
  const auto& t = test::tatb_body;
  const auto& f = test::f2314_body;
  expect_error(replace(t, "\"11.5 GPa\"", "\"-11.5 GPa\""), "shear_modulus", "must be > 0");
  expect_error(replace(t, "hugoniot_s1 = 2.32", "hugoniot_s1 = 1.0"), "hugoniot_s1", "must be > 1");
  expect_error(replace(t, "\"0.80 GPa\"", "0.0"), "yield_stress", "must be > 0");
  expect_error(t + "cowper_symonds_c = -1.0\n", "cowper_symonds_c", "must be >= 0");
  expect_error(t + "cowper_symonds_c = 10.0\n", "cowper_symonds_p", "must be > 0");
  expect_error(t + "hardening_beta = 1.5\n", "hardening_beta", "must lie in");
  expect_error(replace(t, "\"2340 m/s\"", "\"2340 m\""), "sound_speed", "expected");
  expect_error(replace(f, "tait_c = 0.08936", "tait_c = 0.0"), "tait_c", "must be > 0");
  expect_error(replace(f, "tait_c = 0.08936", "tait_c = -0.1"), "tait_c", "must be > 0");
  expect_error(replace(f, "\"0.27 GPa\"", "-2.7e8"), "tait_k0", "must be > 0");
  expect_error(replace(f, "1e-7, 1e-6", "0.0, 1e-6"), "prony_shear_times", "must be > 0");
  expect_error(replace(f, "1e-7, 1e-6", "-1e-7, 1e-6"), "prony_shear_times", "must be > 0");
  expect_error(replace(f, "[\"12.5 MPa\", \"12.5 MPa\"", "[\"-12.5 MPa\", \"12.5 MPa\""), "prony_shear_moduli",
               "must be > 0");
  expect_error(replace(f, "1e-7, 1e-6, ", ""), "prony_shear_times", "has 6 entries");
  expect_error(replace(f, "\"10 MPa\"", "\"-1 MPa\""), "long_term_shear_modulus", "must be >= 0");
  expect_error(replace(f, "\"arrhenius\"", "\"williams\""), "shift", "unknown shift");
  // a plain number is J/mol: 100 meant as kJ/mol would switch the binder's temperature effect off
  expect_error(replace(f, "\"100 kJ/mol\"", "100"), "activation_energy", "100 J/mol is below 1 kJ/mol");
  expect_error(replace(f, "\"2.02 g/cm3\"", "0.0"), "density", "must be > 0");
  expect_error(replace(t, "\"j2_mie_gruneisen\"", "\"j2_mie_grunesen\""), "model", "unknown material model");
  expect_error(t + "shear_modulos = 3.0\n", "shear_modulos", "unknown key");
  expect_error(f + "yield_stress = 3.0\n", "yield_stress", "unknown key for model 'viscoelastic_tait'");
  // non-finite values: toml reads nan and inf as numbers, and inf passed every "> 0" check
  expect_error(replace(t, "\"3e-4 1/K\"", "nan"), "thermal_expansion", "must be a finite number");
  expect_error(replace(t, "\"11.5 GPa\"", "inf"), "shear_modulus", "must be a finite number");
  expect_error(replace(f, "1e-7, 1e-6", "1e-7, inf"), "prony_shear_times", "entry 1 must be a finite number");
  // a temperature far outside the expansion law's range (here 3000 K: a unit slip) is refused
  expect_error(t, "thermal_expansion", "beyond the thermal expansion this model is for", 3000.0);
  // an empty Prony series is no viscoelastic solid (with G_inf = 0 it had no shear stiffness)
  expect_error(replace(replace(f,
                               "[\"12.5 MPa\", \"12.5 MPa\", \"12.5 MPa\", \"12.5 MPa\", \"12.5 MPa\", \"12.5 MPa\", "
                               "\"12.5 MPa\", \"12.5 MPa\"]",
                               "[]"),
                       "[1e-7, 1e-6, 1e-5, 1e-4, 1e-3, 1e-2, 1e-1, 1.0]", "[]"),
               "prony_shear_moduli", "at least one Prony term");
}

TEST(MaterialErrors, PointDriverRejectsBadLoads) {
  EXPECT_THROW(parse_point_path("biaxial"), InputError);
  auto m = test::material_from<3>(test::tatb_body);
  PointLoad load;
  load.path = PointPath::uniaxial_strain, load.strain = -0.01, load.rate = -5.0;
  EXPECT_THROW(drive_point(*m, load), InputError);
  load.rate = 5.0, load.strain = 0.0;
  EXPECT_THROW(drive_point(*m, load), InputError);
  load.strain = 0.01, load.path = PointPath::step_shear, load.rate = 0.0;
  EXPECT_THROW(drive_point(*m, load), InputError);
}
