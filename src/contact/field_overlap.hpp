#pragma once
// How far bodies on different velocity fields have passed into each other. Multi-field contact
// stops approach at shared nodes, but it acts on nodal momenta, not on particle domains, so the
// domains of two grains can still overlap (contact detected late, or a displacement check set
// below the touching distance). The measure: every particle's domain is its initial square (side
// sqrt(V0)) carried by its deformation gradient, the parallelogram F * square centred on the
// particle (the cpGIMP domain; a square of the current area would overlap its neighbours by about
// s eps / 2 under a uniaxial strain eps even with perfect contact, an error of the order of the
// quantity measured). The raster's pixel is a quarter of the smallest initial particle spacing and
// is aligned with the grid origin (a rasterised specimen's domains then tile the raster exactly,
// so a fresh specimen measures zero); the overlap is the area of the pixels whose centres lie in
// the domains of two or more fields. docs/theory/contact.md.
#include <cstdint>
#include <functional>
#include <vector>

#include "grid/grid.hpp"
#include "particles/particles.hpp"

namespace pbx {

class FieldOverlap {
 public:
  // Raster over the grid's extent; pixel side in m (> 0).
  FieldOverlap(const Grid<2>& g, double pixel);
  // Area (m^2 per m of depth) covered by the domains of two or more fields. Parts of domains
  // outside the grid are not counted.
  // With `merge`, the raster of these particles is merged with other processes' (a decomposed run:
  // merge_owners below) before the shared pixels are counted.
  double area(const Particles<2>& P, const std::function<void(std::vector<std::int32_t>&)>& merge = {});
  // A pixel's owner as two rasters together see it (-1 empty, -2 two or more fields, else the field):
  // commutative and associative, so the merge of any number of rasters in any order.
  static std::int32_t merge_owners(std::int32_t a, std::int32_t b) {
    if (a == -1) return b;
    if (b == -1 || a == b) return a;
    return -2;
  }
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
