#include "microstructure/image_import.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <set>

#include <fmt/format.h>

#include "core/error.hpp"
#include "io/deck.hpp"
#include "microstructure/colouring.hpp"
#include "microstructure/png_image.hpp"

namespace pbx {

namespace {

std::uint32_t parse_colour(const DeckTable& t, const std::string& key, std::uint32_t def) {
  if (!t.has(key)) return def;
  const std::string s = t.string(key);
  if (s.size() != 7 || s[0] != '#' || s.find_first_not_of("0123456789abcdefABCDEF", 1) != std::string::npos)
    t.fail(key, fmt::format("expected a colour \"#RRGGBB\" (got \"{}\")", s));
  return static_cast<std::uint32_t>(std::stoul(s.substr(1), nullptr, 16));
}

}  // namespace

ImageSpec read_image_spec(const DeckTable& t, const std::string& file) {
  ImageSpec s;
  s.file = file.empty() ? t.string("image") : file;
  if (!file.empty() && t.has("image")) (void)t.string("image");  // read (so not 'unknown'), overridden by `file`
  s.pixel = t.positive("pixel_size", dim::length);
  s.tatb_density = t.positive("tatb_density", dim::density, 1934.0);
  s.binder_density = t.positive("binder_density", dim::density, 2020.0);
  s.contact_gap = t.non_negative("contact_gap", dim::length, 2e-6);
  if (const auto legend = t.optional_table("legend")) {  // without it: the documented default colours
    s.tatb = parse_colour(*legend, "tatb", s.tatb);
    s.binder = parse_colour(*legend, "binder", s.binder);
    s.void_ = parse_colour(*legend, "void", s.void_);
    if (s.tatb == s.binder || s.tatb == s.void_ || s.binder == s.void_)
      legend->fail("tatb", "the three phase colours must differ");
  }
  return s;
}

Packing import_image(const ImageSpec& spec) {
  const RgbImage img = read_png(spec.file);
  Packing p;
  p.source = spec.file;
  p.periodic = false;
  p.tatb_density = spec.tatb_density;
  p.binder_density = spec.binder_density;
  p.contact_gap = spec.contact_gap;
  PhaseImage& im = p.image;
  im.nx = img.width;
  im.ny = img.height;
  im.pixel = spec.pixel;
  p.box = {im.nx * spec.pixel, im.ny * spec.pixel};
  im.label.assign(static_cast<std::size_t>(im.nx) * im.ny, -2);
  const auto idx = [&](int i, int j) { return static_cast<std::size_t>(j) * im.nx + i; };
  constexpr int kTatb = -3;  // TATB not yet assigned to a grain
  for (int j = 0; j < im.ny; ++j)
    for (int i = 0; i < im.nx; ++i) {
      const std::uint8_t* c = &img.rgb[3 * (static_cast<std::size_t>(im.ny - 1 - j) * im.nx + i)];
      const std::uint32_t rgb = (std::uint32_t(c[0]) << 16) | (std::uint32_t(c[1]) << 8) | c[2];
      if (rgb == spec.tatb)
        im.label[idx(i, j)] = kTatb;
      else if (rgb == spec.binder)
        im.label[idx(i, j)] = -1;
      else if (rgb != spec.void_)
        throw InputError(
            fmt::format("{}: pixel ({}, {}) from the top-left has colour #{:06X}, which is not in "
                        "the legend",
                        spec.file, i, im.ny - 1 - j, rgb));
    }
  // Connected components (4-neighbour flood fill) of the TATB pixels.
  std::vector<std::size_t> stack;
  for (int j = 0; j < im.ny; ++j)
    for (int i = 0; i < im.nx; ++i) {
      if (im.label[idx(i, j)] != kTatb) continue;
      const int g = static_cast<int>(p.grains.size());
      double n = 0, sx = 0, sy = 0;
      stack.push_back(idx(i, j));
      im.label[idx(i, j)] = g;
      while (!stack.empty()) {
        const std::size_t k = stack.back();
        stack.pop_back();
        const int x = static_cast<int>(k % im.nx), y = static_cast<int>(k / im.nx);
        n += 1, sx += x + 0.5, sy += y + 0.5;
        const int nb[4][2] = {{x - 1, y}, {x + 1, y}, {x, y - 1}, {x, y + 1}};
        for (auto& q : nb)
          if (q[0] >= 0 && q[0] < im.nx && q[1] >= 0 && q[1] < im.ny && im.label[idx(q[0], q[1])] == kTatb) {
            im.label[idx(q[0], q[1])] = g;
            stack.push_back(idx(q[0], q[1]));
          }
      }
      Grain gr;
      gr.centre = Eigen::Vector2d(sx / n, sy / n) * spec.pixel;
      gr.diameter = std::sqrt(4.0 * n / std::numbers::pi) * spec.pixel;
      gr.mode = -1;
      p.grains.push_back(gr);
    }
  if (p.grains.empty())
    throw InputError(fmt::format(
        "{}: no pixel has the TATB colour #{:06X} of the legend: there is no grain to simulate", spec.file, spec.tatb));
  // Grains within contact_gap of each other (pixel centres) must get different colours. The search
  // visits (2 reach + 1)^2 pixels around each boundary pixel, so a gap of many pixels (a unit slip,
  // "1 m" for "1 um") would run for hours: refuse it.
  constexpr double kMaxReach = 64;
  if (spec.contact_gap / spec.pixel > kMaxReach)
    throw InputError(
        fmt::format("{}: contact_gap = {:.3g} m spans {:.3g} pixels of {:.3g} m; at most {:.0f} are "
                    "supported (grains that close are neighbours; the paper's binder coats are microns)",
                    spec.file, spec.contact_gap, spec.contact_gap / spec.pixel, spec.pixel, kMaxReach));
  const int reach = static_cast<int>(std::ceil(spec.contact_gap / spec.pixel));
  std::set<std::pair<int, int>> pairs;
  for (int j = 0; j < im.ny; ++j)
    for (int i = 0; i < im.nx; ++i) {
      const int a = im.label[idx(i, j)];
      if (a < 0) continue;
      for (int dj = -reach - 1; dj <= reach + 1; ++dj)
        for (int di = -reach - 1; di <= reach + 1; ++di) {
          const int x = i + di, y = j + dj;
          if (x < 0 || x >= im.nx || y < 0 || y >= im.ny) continue;
          const int b = im.label[idx(x, y)];
          // Adjacent pixels (distance 1) always count, farther ones up to the gap plus one pixel.
          if (b > a && (di * di + dj * dj) * spec.pixel * spec.pixel <= std::pow(spec.contact_gap + spec.pixel, 2))
            pairs.insert({a, b});
        }
    }
  colour_grains(p, {pairs.begin(), pairs.end()});
  measure(p);
  return p;
}

}  // namespace pbx
