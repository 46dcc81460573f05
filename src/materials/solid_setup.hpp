#pragma once
// What every part of a composed material (deviatoric law, EOS) is built from besides its own deck
// keys: the run temperature, the material's reference temperature and its stress-free density at
// the run temperature. Each phase starts stress-free at its own rho0(T), with zero EOS energy.
#include <string>

namespace pbx {

struct SolidSetup {
  std::string name;                      // deck name of the material, for messages
  double temperature = 293.0;            // K, run temperature
  double reference_temperature = 293.0;  // K
  double density = 0;                    // kg/m^3, stress-free at `temperature`
};

// Result of an EOS update: pressure (compression positive) and the tangent bulk modulus
// K = -V dp/dV used for the stable time step.
struct EosResult {
  double pressure = 0;
  double bulk_modulus = 0;
};

}  // namespace pbx
