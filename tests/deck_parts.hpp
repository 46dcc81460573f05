#pragma once
// Pieces of test decks that many tests share (TOML text, units stated): geometry entries and the
// two-grain die specimen. A test writes the rest of its deck itself, so what it varies stays in view.
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

// A [[geometry]] box [x0, x1] x [y0, y1] in mm.
inline std::string box_mm(double x0, double y0, double x1, double y1, const std::string& material) {
  return fmt::format(
      "[[geometry]]\nmin = [\"{:g} mm\", \"{:g} mm\"]\nmax = [\"{:g} mm\", \"{:g} mm\"]\nmaterial = \"{}\"\n", x0, y0,
      x1, y1, material);
}

// The two-grain die specimen (a 0.2 x 0.24 mm die): two grains of radius r_mm side by side at
// mid-height on fields tatb_0 and tatb_1, the binder filling the rest of the box.
inline std::string two_grains_in_binder(double r_mm, const std::string& grain, const std::string& binder) {
  return disk_mm(0.055, 0.12, r_mm, grain, "tatb_0") + disk_mm(0.145, 0.12, r_mm, grain, "tatb_1") +
         box_mm(0, 0, 0.2, 0.24, binder);
}

}  // namespace pbx::test
