#include "microstructure/png_image.hpp"

#include <cstdio>
#include <memory>

#include <fmt/format.h>
#include <png.h>

#include "core/error.hpp"

namespace pbx {

namespace {

struct File {
  std::FILE* f;
  ~File() {
    if (f) std::fclose(f);
  }
};

// libpng reports errors by longjmp; we turn them into exceptions only after png_destroy.
void write_rows(const std::string& file, int width, int height, int depth, int colour_type,
                const std::vector<png_bytep>& rows) {
  File out{std::fopen(file.c_str(), "wb")};
  if (!out.f) throw OutputError(fmt::format("cannot write '{}'", file));
  png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, nullptr, nullptr, nullptr);
  png_infop info = png_create_info_struct(png);
  if (setjmp(png_jmpbuf(png))) {
    png_destroy_write_struct(&png, &info);
    throw OutputError(fmt::format("libpng failed writing '{}'", file));
  }
  png_init_io(png, out.f);
  png_set_IHDR(png, info, width, height, depth, colour_type, PNG_INTERLACE_NONE, PNG_COMPRESSION_TYPE_DEFAULT,
               PNG_FILTER_TYPE_DEFAULT);
  png_write_info(png, info);
  if (depth == 16) png_set_swap(png);
  png_write_image(png, const_cast<png_bytepp>(rows.data()));
  png_write_end(png, nullptr);
  png_destroy_write_struct(&png, &info);
}

}  // namespace

void write_png(const std::string& file, const RgbImage& img) {
  std::vector<png_bytep> rows(img.height);
  for (int y = 0; y < img.height; ++y) rows[y] = const_cast<png_bytep>(img.rgb.data() + 3 * y * img.width);
  write_rows(file, img.width, img.height, 8, PNG_COLOR_TYPE_RGB, rows);
}

void write_png16(const std::string& file, int width, int height, const std::vector<std::uint16_t>& grey) {
  std::vector<png_bytep> rows(height);
  for (int y = 0; y < height; ++y)
    rows[y] = reinterpret_cast<png_bytep>(const_cast<std::uint16_t*>(grey.data() + y * width));
  write_rows(file, width, height, 16, PNG_COLOR_TYPE_GRAY, rows);
}

namespace {

// Reads with the simplified libpng API into the requested format.
std::vector<std::uint8_t> read_any(const std::string& file, png_uint_32 format, int& width, int& height) {
  png_image img{};
  img.version = PNG_IMAGE_VERSION;
  if (!png_image_begin_read_from_file(&img, file.c_str()))
    throw InputError(fmt::format("cannot read PNG '{}': {}", file, img.message));
  img.format = format;
  std::vector<std::uint8_t> buf(PNG_IMAGE_SIZE(img));
  if (!png_image_finish_read(&img, nullptr, buf.data(), 0, nullptr))
    throw InputError(fmt::format("cannot read PNG '{}': {}", file, img.message));
  width = static_cast<int>(img.width);
  height = static_cast<int>(img.height);
  return buf;
}

}  // namespace

RgbImage read_png(const std::string& file) {
  RgbImage out;
  out.rgb = read_any(file, PNG_FORMAT_RGB, out.width, out.height);
  return out;
}

std::vector<std::uint16_t> read_png16(const std::string& file, int& width, int& height) {
  // The simplified API would apply gamma to 16-bit data, so read the raw samples.
  File in{std::fopen(file.c_str(), "rb")};
  if (!in.f) throw InputError(fmt::format("cannot open '{}'", file));
  png_structp png = png_create_read_struct(PNG_LIBPNG_VER_STRING, nullptr, nullptr, nullptr);
  png_infop info = png_create_info_struct(png);
  std::vector<std::uint16_t> out;
  std::vector<png_bytep> rows;
  if (setjmp(png_jmpbuf(png))) {
    png_destroy_read_struct(&png, &info, nullptr);
    throw InputError(fmt::format("cannot read 16-bit PNG '{}'", file));
  }
  png_init_io(png, in.f);
  png_read_info(png, info);
  width = static_cast<int>(png_get_image_width(png, info));
  height = static_cast<int>(png_get_image_height(png, info));
  if (png_get_bit_depth(png, info) != 16 || png_get_color_type(png, info) != PNG_COLOR_TYPE_GRAY)
    png_error(png, "not 16-bit grey");
  png_set_swap(png);
  out.resize(static_cast<std::size_t>(width) * height);
  rows.resize(height);
  for (int y = 0; y < height; ++y) rows[y] = reinterpret_cast<png_bytep>(out.data() + y * width);
  png_read_image(png, rows.data());
  png_destroy_read_struct(&png, &info, nullptr);
  return out;
}

}  // namespace pbx
