#pragma once
// Packing from a segmented micrograph: every pixel's colour is looked up in a legend (one colour per
// phase); 4-connected TATB regions become grains (centroid, area-equivalent diameter); grains whose
// pixels come within contact_gap of each other get different contact colours.
#include <string>

#include "microstructure/packing.hpp"

namespace pbx {

class DeckTable;

struct ImageSpec {
  std::string file;
  double pixel = 1e-6;                                                 // m, side of a square pixel
  std::uint32_t tatb = 0xFFFF00, binder = 0x008000, void_ = 0xFFFFFF;  // legend, 0xRRGGBB
  double tatb_density = 1934, binder_density = 2020;                   // kg/m3
  double contact_gap = 2e-6;                                           // m
};

// Reads the image keys of a [packing] table; `file` overrides the table's `image` key when non-empty.
ImageSpec read_image_spec(const DeckTable& t, const std::string& file);
Packing import_image(const ImageSpec& spec);

}  // namespace pbx
