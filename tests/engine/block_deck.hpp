#pragma once
// A homogeneous linear-elastic column filling the die (TATB-like moduli: K = 10.59 GPa,
// G = 11.5 GPa, nu = 0.101), compressed by the punch at 0.3 m/s. Uniaxial strain does not depend
// on the width, so the column is narrow (4 cells) and tall (48 cells): the punch constraint acts
// on the first node row at or behind its face, which lets the top layer lag the face by a few
// hundredths of a cell (a sawtooth in d/h); over a stroke of several cells this averages out.
#include <string>

#include <fmt/format.h>

namespace pbx::test {

// width and height in mm (the default: the narrow, tall column above)
inline std::string block_deck(double mass_scaling, double end_strain = 0.04, const char* integrator = "usl",
                              const char* kernel = "ugimp", double width_mm = 0.04, double height_mm = 0.48) {
  return fmt::format(R"(
[run]
end_strain = {0}
history_points = 201
snapshots = 0
[grid]
cell_size = "10 um"
shape_function = "{1}"
particles_per_cell = 2
[solver]
integrator = "{2}"
cfl = 0.4
mass_scaling = {3}
[die]
width = "{4} mm"
height = "{5} mm"
punch_velocity = "0.3 m/s"
ramp_strain = 0.004
[materials.block]
model = "linear_elastic"
density = "1.934 g/cm3"
bulk_modulus = "10.59 GPa"
shear_modulus = "11.5 GPa"
[[geometry]]
min = ["0 mm", "0 mm"]
max = ["{4} mm", "{5} mm"]
material = "block"
)",
                     end_strain, kernel, integrator, mass_scaling, width_mm, height_mm);
}

}  // namespace pbx::test
