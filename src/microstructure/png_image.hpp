#pragma once
// PNG files through libpng: 8-bit RGB for pictures and segmented micrographs, 16-bit grey for
// label maps. Rows are stored top first, as in the file.
#include <cstdint>
#include <string>
#include <vector>

namespace pbx {

struct RgbImage {
  int width = 0, height = 0;
  std::vector<std::uint8_t> rgb;  // width*height*3, row 0 = top
};

void write_png(const std::string& file, const RgbImage& img);
RgbImage read_png(const std::string& file);  // any PNG, converted to 8-bit RGB; InputError on failure

void write_png16(const std::string& file, int width, int height, const std::vector<std::uint16_t>& grey);
std::vector<std::uint16_t> read_png16(const std::string& file, int& width, int& height);

}  // namespace pbx
