#pragma once
// Two elastic disks (radius 60 um, E = 1 GPa, nu = 0.3, 2 g/cm3) on separate fields meeting head-on
// at +-20 m/s on a 10 um grid: the collision of test_two_disks.cpp and test_field_overlap.cpp.
// `contact_lines` are added to the [contact] table after `default = law`.
#include <string>

namespace pbx::test {

inline std::string two_disks_deck(const std::string& law, const std::string& end_time = "12 us",
                                  int history_points = 60, const std::string& contact_lines = "") {
  return R"(
[run]
end_time = ")" +
         end_time + R"("
history_points = )" +
         std::to_string(history_points) + R"(
snapshots = 0
[grid]
cell_size = "10 um"
min = ["-0.2 mm", "-0.05 mm"]
max = ["0.6 mm", "0.25 mm"]
[materials.left]
model = "linear_elastic"
density = "2.0 g/cm3"
youngs_modulus = "1 GPa"
poisson_ratio = 0.3
[materials.right]
model = "linear_elastic"
density = "2.0 g/cm3"
youngs_modulus = "1 GPa"
poisson_ratio = 0.3
[contact]
default = ")" +
         law + "\"\n" + contact_lines + R"(
[[geometry]]
shape = "disk"
center = ["0.1 mm", "0.1 mm"]
radius = "0.06 mm"
material = "left"
velocity = ["20 m/s", "0 m/s"]
[[geometry]]
shape = "disk"
center = ["0.3 mm", "0.1 mm"]
radius = "0.06 mm"
material = "right"
velocity = ["-20 m/s", "0 m/s"]
)";
}

}  // namespace pbx::test
