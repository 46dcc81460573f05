#pragma once
// Shared fixtures of the material tests: build a material from a TOML snippet, and the paper's
// parameter sets as deck text.
#include <memory>
#include <string>

#include "io/deck.hpp"
#include "materials/material.hpp"

namespace pbx::test {

template <int D>
std::unique_ptr<Material<D>> material_from(const std::string& body, double T = 293.0, const std::string& name = "m") {
  const Deck deck = Deck::from_string("[materials." + name + "]\n" + body, "test.toml");
  MaterialContext ctx;
  ctx.temperature = T;
  ctx.name = name;
  auto m = make_material<D>(deck.root().table("materials").table(name), ctx);
  deck.check_unused();
  return m;
}

// Table 1 TATB with the J2 deviator and Mie-Grueneisen EOS.
inline const std::string tatb_body = R"(
model = "j2_mie_gruneisen"
density = "1.934 g/cm3"
thermal_expansion = "3e-4 1/K"
shear_modulus = "11.5 GPa"
yield_stress = "0.80 GPa"
sound_speed = "2340 m/s"
hugoniot_s1 = 2.32
gruneisen_gamma0 = 1.60
)";

// The F2314 calibration set of examples/materials/f2314.toml.
inline const std::string f2314_body = R"(
model = "viscoelastic_tait"
density = "2.02 g/cm3"
thermal_expansion = "4.5e-4 1/K"
long_term_shear_modulus = "10 MPa"
prony_shear_moduli = ["12.5 MPa", "12.5 MPa", "12.5 MPa", "12.5 MPa", "12.5 MPa", "12.5 MPa", "12.5 MPa", "12.5 MPa"]
prony_shear_times = [1e-7, 1e-6, 1e-5, 1e-4, 1e-3, 1e-2, 1e-1, 1.0]
shift = "arrhenius"
activation_energy = "100 kJ/mol"
tait_c = 0.08936
tait_k0 = "0.27 GPa"
tait_b1 = "4e-3 1/K"
)";

}  // namespace pbx::test
