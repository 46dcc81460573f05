#pragma once
// How far bodies on different velocity fields have passed into each other. Multi-field contact
// stops approach at shared nodes, but it acts on nodal momenta, not on particle domains, so the
// domains of two grains can still overlap (contact detected late, or a displacement check set
// below the touching distance). The measure: every particle's domain drawn as the axis-aligned
// square of its current area centred on its position (the uGIMP particle domain), on a raster
// whose pixel is a quarter of the smallest initial particle spacing and is aligned with the grid
// origin (a rasterised specimen's domains then tile the raster exactly, so a fresh specimen
// measures zero); the overlap is the area of the pixels whose centres lie in the domains of two or
// more fields. Squares ignore the shear of the domain (F = R U with U ~ 1 at the strains of a die
// test); docs/theory/contact.md.
#include <cstdint>
#include <vector>

#include "grid/grid.hpp"
#include "particles/particles.hpp"

namespace pbx {

class FieldOverlap {
 public:
  FieldOverlap() = default;
  // Raster over the grid's extent; pixel side in m (> 0).
  FieldOverlap(const Grid<2>& g, double pixel);
  // Area (m^2 per m of depth) covered by the domains of two or more fields. Parts of domains
  // outside the grid are not counted.
  double area(const Particles<2>& P);
  double pixel() const { return pixel_; }
  // A quarter of the side of the smallest initial particle domain (sqrt of the least volume0).
  static double default_pixel(const Particles<2>& P);

 private:
  double pixel_ = 0;
  Vec<2> origin_ = Vec<2>::Zero();
  long nx_ = 0, ny_ = 0;
  std::vector<std::int32_t> owner_;  // -1: empty; -2: two or more fields; else the one field
};

}  // namespace pbx
