// packing.csv (one row per grain, the header comments carry the box and phase data needed to read
// it back), packing.json (achieved statistics, for people and reports), packing.png (picture like
// the paper's Fig. 1a) and, for imported packings, phases.png (16-bit label map).
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

#include <fmt/format.h>

#include "core/error.hpp"
#include "core/parse_number.hpp"
#include "io/atomic_write.hpp"
#include "io/json.hpp"
#include "microstructure/bitmap_text.hpp"
#include "microstructure/packing.hpp"
#include "microstructure/phase_map.hpp"
#include "microstructure/png_image.hpp"
#include "pbxmpm_git.hpp"  // PBXMPM_GIT, generated at build time

namespace pbx {

namespace {

// Grain tints by contact colour (TATB is yellow in micrographs): distinct, all light.
constexpr std::uint8_t kPalette[][3] = {{240, 200, 60}, {230, 140, 50},  {200, 220, 90}, {250, 225, 140},
                                        {215, 170, 90}, {245, 180, 110}, {190, 190, 60}, {255, 210, 170}};

// Scale-bar length: the largest 1, 2 or 5 x 10^k um not over 15 % of the box width (100 um for the
// paper's 1 mm wide box).
double scale_bar_um(const Packing& p) {
  const double limit_um = 0.15 * p.box.x() * 1e6;
  double best = 1;
  for (int k = -3; std::pow(10.0, k) <= limit_um; ++k)  // pow: exact powers of ten, 100 and not 100.00000000000001
    for (double m : {1.0, 2.0, 5.0})
      if (m * std::pow(10.0, k) <= limit_um * (1 + 1e-12)) best = m * std::pow(10.0, k);
  return best;
}

constexpr std::uint8_t kBinder[3] = {30, 90, 40}, kBlack[3] = {0, 0, 0}, kWhite[3] = {255, 255, 255};

void fill(RgbImage& img, int x0, int y0, int w, int h, const std::uint8_t rgb[3]) {
  for (int j = std::max(0, y0); j < std::min(img.height, y0 + h); ++j)
    for (int i = std::max(0, x0); i < std::min(img.width, x0 + w); ++i)
      std::copy_n(rgb, 3, &img.rgb[3 * (static_cast<std::size_t>(j) * img.width + i)]);
}

RgbImage picture(const Packing& p) {
  const double px = p.box.maxCoeff() / 1200.0;
  RgbImage img;
  img.width = static_cast<int>(std::lround(p.box.x() / px));
  img.height = static_cast<int>(std::lround(p.box.y() / px));
  img.rgb.assign(static_cast<std::size_t>(img.width) * img.height * 3, 255);
  PhaseMap map(p);
  for (int j = 0; j < img.height; ++j)
    for (int i = 0; i < img.width; ++i) {
      const PhaseHit h = map.at({(i + 0.5) * px, (img.height - j - 0.5) * px});
      std::uint8_t* c = &img.rgb[3 * (static_cast<std::size_t>(j) * img.width + i)];
      if (h.phase == MesoPhase::tatb) {
        const int col = p.grains[h.grain].colour;
        std::copy_n(kPalette[col % 8], 3, c);
      } else if (h.phase == MesoPhase::binder) {
        std::copy_n(kBinder, 3, c);
      }
    }
  // Below the box, a white strip (a picture without a scale cannot be read against a micrograph):
  // first a black scale bar, 8 px thick, from 20 px from the left and 17 px below the box, with its
  // length written 10 px to its right (text cells from 12 px below the box); then the legend, a
  // swatch with a black rim and its label per phase, in lines of 28 px (text at scale 2; scale 1 in
  // a picture narrower than 600 px), wrapping where the picture ends.
  const int box_h = img.height, scale = img.width >= 600 ? 2 : 1;
  const int cell = std::max(kGlyphRows * scale, 18), line = cell + 10, gap = 24, swatch = 18;
  const double bar_um = scale_bar_um(p);
  const int bar_px = static_cast<int>(std::lround(bar_um * 1e-6 / px));
  const std::string bar_label = fmt::format("{:g} \u00b5m", bar_um);
  const char* labels[] = {"TATB grain (tinted by colour)", "binder coat (dark green)", "pore (white)"};
  struct Item {
    int x, line, width;
  };
  std::vector<Item> items;
  int x = 20, lines = 1;
  auto place = [&](int width) {
    if (x > 20 && x + width > img.width - 10) x = 20, ++lines;
    items.push_back({x, lines - 1, width});
    x += width + gap;
  };
  place(bar_px + 10 + text_width(bar_label, scale));
  for (const char* l : labels) place(swatch + 6 + text_width(l, scale));
  img.height += 12 + lines * line;
  img.rgb.resize(static_cast<std::size_t>(img.width) * img.height * 3, 255);
  auto top_of = [&](const Item& it) { return box_h + 12 + it.line * line; };
  auto text_top = [&](const Item& it) { return top_of(it) + (cell - kGlyphRows * scale) / 2; };
  fill(img, items[0].x, top_of(items[0]) + 5, bar_px, 8, kBlack);
  draw_text(img, items[0].x + bar_px + 10, text_top(items[0]), bar_label, scale, kBlack);
  for (int k = 0; k < 3; ++k) {
    const Item& it = items[1 + k];
    const int sy = top_of(it) + (cell - swatch) / 2;
    fill(img, it.x, sy, swatch, swatch, kBlack);
    if (k == 0) {  // three of the grain tints side by side
      for (int t = 0; t < 3; ++t) fill(img, it.x + 1 + 16 * t / 3, sy + 1, 16 / 3 + (t == 2 ? 1 : 0), 16, kPalette[t]);
    } else {
      fill(img, it.x + 1, sy + 1, swatch - 2, swatch - 2, k == 1 ? kBinder : kWhite);
    }
    draw_text(img, it.x + swatch + 6, text_top(it), labels[k], scale, kBlack);
  }
  return img;
}

}  // namespace

void write_packing(const Packing& p, const std::string& dir) {
  std::filesystem::create_directories(dir);
  const auto path = [&](const char* f) { return (std::filesystem::path(dir) / f).string(); };
  {
    std::ostringstream csv;
    csv << fmt::format("# pbxmpm packing {} ({})\n", PBXMPM_VERSION, PBXMPM_GIT);
    csv << fmt::format("# box_width_m = {:.17g}\n# box_height_m = {:.17g}\n", p.box.x(), p.box.y());
    csv << fmt::format("# periodic = {}\n# seed = {}\n", p.periodic ? 1 : 0, p.seed);
    csv << fmt::format("# tatb_density_kg_m3 = {:.17g}\n# binder_density_kg_m3 = {:.17g}\n", p.tatb_density,
                       p.binder_density);
    csv << fmt::format("# contact_gap_m = {:.17g}\n", p.contact_gap);
    if (p.image.nx > 0)
      csv << fmt::format("# image_nx = {}\n# image_ny = {}\n# image_pixel_m = {:.17g}\n", p.image.nx, p.image.ny,
                         p.image.pixel);
    csv << "grain,x_m,y_m,diameter_m,coat_m,colour,mode\n";
    for (std::size_t i = 0; i < p.grains.size(); ++i) {
      const Grain& g = p.grains[i];
      csv << fmt::format("{},{:.17g},{:.17g},{:.17g},{:.17g},{},{}\n", i, g.centre.x(), g.centre.y(), g.diameter,
                         g.coat, g.colour, g.mode);
    }
    write_text_atomically(path("packing.csv"), csv.str());
  }
  {
    const PackingStats& s = p.stats;
    // Diameter histogram: 25 um bins from 0 to the largest grain.
    double dmax = 0;
    for (const auto& g : p.grains) dmax = std::max(dmax, g.diameter);
    const double bin = 25e-6;
    std::vector<int> hist(static_cast<std::size_t>(std::floor(dmax / bin)) + 1, 0);
    for (const auto& g : p.grains) ++hist[static_cast<std::size_t>(std::floor(g.diameter / bin))];
    Json h = Json::array();
    for (std::size_t k = 0; k < hist.size(); ++k)
      h.push_back({{"from_um", k * 25}, {"to_um", (k + 1) * 25}, {"count", hist[k]}});
    Json js;
    js["code_version"] = fmt::format("pbxmpm {} ({})", PBXMPM_VERSION, PBXMPM_GIT);
    js["source"] = p.source;
    js["seed"] = p.seed;
    js["periodic"] = p.periodic;
    js["box_m"] = json_numbers({p.box.x(), p.box.y()});
    js["picture"] = fmt::format(
        "packing.png: TATB tinted by contact colour (light tints), binder dark green, voids white; "
        "the black bar below the box is {:g} um long (its length written beside it), then a legend",
        scale_bar_um(p));
    js["scale_bar_um"] = scale_bar_um(p);
    js["porosity"] = s.porosity;
    js["density_kg_m3"] = s.density;
    js["tmd_kg_m3"] = s.tmd;
    js["tatb_density_kg_m3"] = p.tatb_density;
    js["binder_density_kg_m3"] = p.binder_density;
    js["tatb_area_fraction"] = s.tatb_area_fraction;
    js["binder_area_fraction"] = s.binder_area_fraction;
    js["tatb_mass_fraction"] = s.tatb_mass_fraction;
    js["binder_mass_fraction"] = 1.0 - s.tatb_mass_fraction;
    js["grains"] = p.grains.size();
    js["grains_coarse"] = s.grains_coarse;
    js["grains_fine"] = s.grains_fine;
    js["coat_min_m"] = s.coat_min;
    js["coat_max_m"] = s.coat_max;
    js["grains_shrunk"] = p.grains_shrunk;
    js["max_relative_shrink"] = p.max_shrink;
    js["attempt"] = p.attempt;
    js["tiles"] = json_numbers({static_cast<double>(p.tiles[0]), static_cast<double>(p.tiles[1])});
    js["colours"] = s.colours;
    js["contact_gap_m"] = p.contact_gap;
    js["diameter_histogram"] = h;
    json_write_file(path("packing.json"), js);
  }
  write_png(path("packing.png"), picture(p));
  if (p.image.nx > 0) {
    std::vector<std::uint16_t> grey(p.image.label.size());
    // Stored top row first like any PNG; labels shifted by 2 so void (-2) is 0.
    for (int j = 0; j < p.image.ny; ++j)
      for (int i = 0; i < p.image.nx; ++i)
        grey[static_cast<std::size_t>(p.image.ny - 1 - j) * p.image.nx + i] =
            static_cast<std::uint16_t>(p.image.label[static_cast<std::size_t>(j) * p.image.nx + i] + 2);
    write_png16(path("phases.png"), p.image.nx, p.image.ny, grey);
  }
}

Packing read_packing(const std::string& dir) {
  const std::string file = (std::filesystem::path(dir) / "packing.csv").string();
  std::ifstream in(file);
  if (!in) throw InputError(fmt::format("cannot open packing '{}'", file));
  Packing p;
  std::string line;
  int lineno = 0;
  std::vector<int> grain_line;  // the file line of each grain, for the messages
  bool header = false;
  auto bad = [&](const std::string& what) { throw InputError(fmt::format("{}:{}: {}", file, lineno, what)); };
  while (std::getline(in, line)) {
    ++lineno;
    if (line.empty()) continue;
    if (line[0] == '#') {
      const auto eq = line.find('=');
      if (eq == std::string::npos) continue;
      std::string key = line.substr(1, eq - 1);
      key.erase(0, key.find_first_not_of(' '));
      key.erase(key.find_last_not_of(' ') + 1);
      const std::string val = line.substr(eq + 1);
      try {
        if (key == "box_width_m")
          p.box.x() = std::stod(val);
        else if (key == "box_height_m")
          p.box.y() = std::stod(val);
        else if (key == "periodic")
          p.periodic = std::stoi(val) != 0;
        else if (key == "seed")
          p.seed = std::stoull(val);
        else if (key == "tatb_density_kg_m3")
          p.tatb_density = std::stod(val);
        else if (key == "binder_density_kg_m3")
          p.binder_density = std::stod(val);
        else if (key == "contact_gap_m")
          p.contact_gap = std::stod(val);
        else if (key == "image_nx")
          p.image.nx = std::stoi(val);
        else if (key == "image_ny")
          p.image.ny = std::stoi(val);
        else if (key == "image_pixel_m")
          p.image.pixel = std::stod(val);
      } catch (const std::exception&) {
        bad("cannot read the value of '" + key + "'");
      }
      continue;
    }
    if (!header) {
      if (line != "grain,x_m,y_m,diameter_m,coat_m,colour,mode") bad("unexpected column header");
      header = true;
      continue;
    }
    std::stringstream ss(line);
    std::string f[7];
    for (auto& x : f)
      if (!std::getline(ss, x, ',')) bad("expected 7 columns");
    // every cell whole: stod/stoi read a prefix ("0.4abc") and throw out_of_range on overflow
    auto real = [&](const std::string& x) {
      const auto v = parse_finite(x);
      if (!v) bad("'" + x + "' is not a finite number");
      return v.value_or(0.0);
    };
    auto whole = [&](const std::string& x) {
      const double v = real(x);
      if (v != std::floor(v) || std::fabs(v) > 1e6) bad("'" + x + "' is not a small integer");
      return static_cast<int>(v);
    };
    Grain g;
    g.centre = {real(f[1]), real(f[2])};
    g.diameter = real(f[3]);
    g.coat = real(f[4]);
    g.colour = whole(f[5]);
    g.mode = whole(f[6]);
    if (!(g.diameter > 0) || !(g.coat >= 0) || g.colour < 0) bad("diameter, coat or colour out of range");
    p.grains.push_back(g);
    grain_line.push_back(lineno);
  }
  if (!(p.box.x() > 0 && p.box.y() > 0) || !(p.tatb_density > 0) || !(p.binder_density > 0))
    throw InputError(fmt::format("{}: the header lacks the box size or the phase densities", file));
  const double box_max = std::max(p.box.x(), p.box.y());
  for (std::size_t i = 0; i < p.grains.size(); ++i) {
    const Grain& g = p.grains[i];
    // a grain or coat larger than the box is a typo or a unit slip (mm written as m), and would
    // pass the position check below for any centre
    if (g.diameter > box_max || g.coat > box_max)
      throw InputError(fmt::format("{}:{}: grain {} has diameter {} m and coat {} m, larger than the {} x {} m box",
                                   file, grain_line[i], i, g.diameter, g.coat, p.box[0], p.box[1]));
    for (int d = 0; d < 2; ++d)
      if (g.centre[d] < -0.5 * g.diameter || g.centre[d] > p.box[d] + 0.5 * g.diameter)
        throw InputError(fmt::format("{}: grain {} at ({}, {}) m lies outside the {} x {} m box", file, i, g.centre[0],
                                     g.centre[1], p.box[0], p.box[1]));
  }
  // Two grains on the same centre (a row pasted twice) would stack two cores in one place, which
  // no packing has; cores closer than a thousandth of the smaller radius count as the same place.
  {
    std::vector<std::size_t> order(p.grains.size());
    for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
    std::sort(order.begin(), order.end(),
              [&](std::size_t a, std::size_t b) { return p.grains[a].centre.x() < p.grains[b].centre.x(); });
    for (std::size_t a = 0; a < order.size(); ++a)
      for (std::size_t b = a + 1; b < order.size(); ++b) {
        const Grain &ga = p.grains[order[a]], &gb = p.grains[order[b]];
        const double tol = 5e-4 * std::min(ga.diameter, gb.diameter);
        if (gb.centre.x() - ga.centre.x() > tol) break;
        if ((ga.centre - gb.centre).norm() <= tol) {
          const auto [i, j] = std::minmax(order[a], order[b]);
          throw InputError(fmt::format("{}:{}: grain {} has the centre of grain {} (line {}): a duplicated row?", file,
                                       grain_line[j], j, i, grain_line[i]));
        }
      }
  }
  if (p.image.nx > 0) {
    p.source = "image";
    int w = 0, h = 0;
    const auto grey = read_png16((std::filesystem::path(dir) / "phases.png").string(), w, h);
    if (w != p.image.nx || h != p.image.ny) throw InputError(fmt::format("{}: phases.png size differs", file));
    p.image.label.resize(grey.size());
    for (int j = 0; j < h; ++j)
      for (int i = 0; i < w; ++i)
        p.image.label[static_cast<std::size_t>(j) * w + i] = grey[static_cast<std::size_t>(h - 1 - j) * w + i] - 2;
  }
  measure(p);
  return p;
}

}  // namespace pbx
