#pragma once
// A homogeneous linear-elastic column filling the die (TATB-like moduli: K = 10.59 GPa,
// G = 11.5 GPa, nu = 0.101), compressed by the punch at 0.3 m/s. Uniaxial strain does not depend
// on the width, so the column is narrow (4 cells) and tall (48 cells): the punch constraint acts
// on the first node row at or behind its face, which lets the top layer lag the face by a few
// hundredths of a cell (a sawtooth in d/h); over a stroke of several cells this averages out.
#include <string>

#include <fmt/format.h>

namespace pbx::test {

inline std::string block_deck(double mass_scaling, double end_strain = 0.04, const char* integrator = "usl",
                              const char* kernel = "ugimp") {
  return fmt::format(R"(
[run]
end_strain = {}
history_points = 201
snapshots = 0
[grid]
cell_size = "10 um"
shape_function = "{}"
particles_per_cell = 2
[solver]
integrator = "{}"
cfl = 0.4
mass_scaling = {}
[die]
width = "0.04 mm"
height = "0.48 mm"
punch_velocity = "0.3 m/s"
ramp_strain = 0.004
[materials.block]
model = "linear_elastic"
density = "1.934 g/cm3"
bulk_modulus = "10.59 GPa"
shear_modulus = "11.5 GPa"
[[geometry]]
min = ["0 mm", "0 mm"]
max = ["0.04 mm", "0.48 mm"]
material = "block"
)", end_strain, kernel, integrator, mass_scaling);
}

}  // namespace pbx::test
