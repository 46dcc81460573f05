#pragma once
// Pieces of test decks that many tests share (TOML text, units stated): linear-elastic materials,
// geometry entries, rigid boxes and the two-grain die specimen. A test writes the rest of its deck itself, so what it
// varies stays in view.
#include <string>

#include <fmt/format.h>

namespace pbx::test {

// A [[geometry]] disk, centre and radius in mm, on `field` when given (else the material's field).
inline std::string disk_mm(double cx, double cy, double r, const std::string& material, const std::string& field = "") {
  return fmt::format(
      "[[geometry]]\nshape = \"disk\"\ncenter = [\"{:g} mm\", \"{:g} mm\"]\nradius = \"{:g} mm\"\n"
      "material = \"{}\"\n{}",
      cx, cy, r, material, field.empty() ? std::string() : "field = \"" + field + "\"\n");
}

// A [[geometry]] box [x0, x1] x [y0, y1] in mm, on `field` when given (else the material's field).
inline std::string box_mm(double x0, double y0, double x1, double y1, const std::string& material,
                          const std::string& field = "") {
  return fmt::format(
      "[[geometry]]\nmin = [\"{:g} mm\", \"{:g} mm\"]\nmax = [\"{:g} mm\", \"{:g} mm\"]\nmaterial = \"{}\"\n{}", x0, y0,
      x1, y1, material, field.empty() ? std::string() : "field = \"" + field + "\"\n");
}

// A [materials.NAME] table of the linear-elastic law: density in g/cm3, Young's modulus in GPa.
inline std::string elastic(const std::string& name, double rho_g_cm3, double youngs_GPa, double poisson) {
  return fmt::format(
      "[materials.{}]\nmodel = \"linear_elastic\"\ndensity = \"{:g} g/cm3\"\nyoungs_modulus = \"{:g} GPa\"\n"
      "poisson_ratio = {:g}\n",
      name, rho_g_cm3, youngs_GPa, poisson);
}

// A [[rigid]] box [x0, x1] x [y0, y1] in mm whose contact face has the unit normal (nx, ny),
// followed by `more` (TOML lines: contact, friction, velocity, ...).
inline std::string rigid_box_mm(const std::string& name, double x0, double y0, double x1, double y1, int nx, int ny,
                                const std::string& more = "") {
  return fmt::format(
      "[[rigid]]\nname = \"{}\"\nmin = [\"{:g} mm\", \"{:g} mm\"]\nmax = [\"{:g} mm\", \"{:g} mm\"]\n"
      "normal = [{}, {}]\n{}",
      name, x0, y0, x1, y1, nx, ny, more);
}

// The two-grain die specimen (a 0.2 x 0.24 mm die): two grains of radius r_mm side by side at
// mid-height on fields tatb_0 and tatb_1, the binder filling the rest of the box.
inline std::string two_grains_in_binder(double r_mm, const std::string& grain, const std::string& binder) {
  return disk_mm(0.055, 0.12, r_mm, grain, "tatb_0") + disk_mm(0.145, 0.12, r_mm, grain, "tatb_1") +
         box_mm(0, 0, 0.2, 0.24, binder);
}

}  // namespace pbx::test
