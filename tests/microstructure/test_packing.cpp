// Generated packings: geometry, mass balance, porosity, colouring, determinism and bad decks.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <sstream>

#include <unistd.h>

#include <fmt/format.h>
#include <gtest/gtest.h>

#include "microstructure/bitmap_text.hpp"
#include "microstructure/png_image.hpp"

#include "core/error.hpp"
#include "io/deck.hpp"
#include "microstructure/colouring.hpp"
#include "microstructure/packing.hpp"
#include "microstructure/union_area.hpp"

using namespace pbx;

namespace {

const char* kDeck = R"([packing]
box = ["1.0 mm", "1.2 mm"]
porosity = 0.0932
mass_ratio = [95, 5]
diameter_min = "50 um"
diameter_max = "300 um"
seed = 3
[packing.coarse]
mean = "260 um"
spread = "30 um"
share = 0.75
[packing.fine]
mean = "70 um"
spread = "20 um"
share = 0.25
)";

PackingSpec spec_from(const std::string& text) {
  Deck d = Deck::from_string(text, "pack.toml");
  PackingSpec s = read_packing_spec(d.root().table("packing"));
  d.check_unused();
  return s;
}

std::string replace(std::string s, const std::string& from, const std::string& to) {
  const auto at = s.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  return s.replace(at, from.size(), to);
}

std::string error_of(const std::string& text) {
  try {
    generate_packing(spec_from(text));
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

std::string slurp(const std::filesystem::path& f) {
  std::ifstream in(f, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

const Packing& paper_packing() {
  static const Packing p = generate_packing(spec_from(kDeck));
  return p;
}

}  // namespace

TEST(Packing, TmdAndBinderAreaFromPhaseDensities) {
  const PackingSpec s = spec_from(kDeck);
  // 1 / (0.95/1.934 + 0.05/2.02) g/cm3 (the paper quotes 1.942, see docs).
  EXPECT_NEAR(s.tmd(), 1938.126, 0.001);
  EXPECT_NEAR(s.binder_per_tatb_area(), (5.0 / 95.0) * (1934.0 / 2020.0), 1e-15);
}

TEST(Packing, GrainsNeverOverlapAndStayInTheBox) {
  const Packing& p = paper_packing();
  ASSERT_GT(p.grains.size(), 20u);
  for (std::size_t i = 0; i < p.grains.size(); ++i) {
    const Grain& a = p.grains[i];
    EXPECT_TRUE(a.centre.x() >= 0 && a.centre.x() < p.box.x() && a.centre.y() >= 0 && a.centre.y() < p.box.y());
    EXPECT_TRUE(a.diameter >= 50e-6 && a.diameter <= 300e-6);
    for (std::size_t j = i + 1; j < p.grains.size(); ++j) {
      const Grain& b = p.grains[j];
      Eigen::Vector2d d = b.centre - a.centre;
      for (int k = 0; k < 2; ++k) d[k] -= p.box[k] * std::round(d[k] / p.box[k]);  // periodic images
      EXPECT_GE(d.norm(), 0.5 * (a.diameter + b.diameter)) << i << " " << j;
    }
  }
}

TEST(Packing, PorosityMassRatioAndCoatsAreAsSpecified) {
  const Packing& p = paper_packing();
  const PackingStats& s = p.stats;
  EXPECT_NEAR(s.porosity, 0.0932, 0.002);
  EXPECT_NEAR(s.tatb_mass_fraction, 0.95, 1e-9);  // exact mass balance (bisection to round-off)
  EXPECT_NEAR(s.density, (1 - s.porosity) * s.tmd, 1e-9);
  // Periodic packing: each grain's TATB area is in the box exactly once.
  double tatb = 0;
  for (const auto& g : p.grains) tatb += 0.25 * std::numbers::pi * g.diameter * g.diameter;
  EXPECT_NEAR(s.tatb_area_fraction, tatb / p.box.prod(), 1e-9);
  // Proportional coats: one thickness-to-diameter ratio, at least the no-overlap value
  // (sqrt(1 + beta) - 1)/2 = 0.012443 because overlapping coats hide some binder.
  const double ratio = p.grains[0].coat / p.grains[0].diameter;
  for (const auto& g : p.grains) EXPECT_NEAR(g.coat / g.diameter, ratio, 1e-12);
  const double beta = (5.0 / 95.0) * (1934.0 / 2020.0);
  EXPECT_GT(ratio, 0.5 * (std::sqrt(1 + beta) - 1));
  EXPECT_LT(ratio, 0.03);
}

TEST(Packing, UniformCoatHasOneThickness) {
  const Packing p = generate_packing(spec_from(replace(kDeck, "seed = 3", "seed = 3\ncoat = \"uniform\"")));
  for (const auto& g : p.grains) EXPECT_DOUBLE_EQ(g.coat, p.grains[0].coat);
  EXPECT_NEAR(p.stats.tatb_mass_fraction, 0.95, 1e-9);
}

TEST(Packing, ColouringSeparatesEveryContact) {
  const Packing& p = paper_packing();
  const auto pairs = contact_pairs(p);
  EXPECT_GT(pairs.size(), p.grains.size());  // a dense packing: more contacts than grains
  for (auto [i, j] : pairs) EXPECT_NE(p.grains[i].colour, p.grains[j].colour) << i << " " << j;
  EXPECT_GE(p.stats.colours, 3);
  EXPECT_LE(p.stats.colours, 8);
}

// The colours the packer gives respect its 2 um contact gap; at a 20 um grid grains of one colour
// whose cores come within 2 cells would share nodes (one body, no contact law). The run re-colours
// them apart (solver/scene.cpp); a distance the colours already respect keeps them unchanged.
TEST(Packing, ColoursAreSeparatedOverTheGridsReach) {
  Packing p = paper_packing();
  const double reach = 2 * 20e-6;
  int before = 0;
  for (auto [i, j] : core_pairs(p, reach)) before += p.grains[i].colour == p.grains[j].colour;
  ASSERT_GT(before, 0) << "the test needs a packing with same-colour grains within the reach";
  Packing kept = p;
  EXPECT_EQ(separate_colours_within(kept, 1e-9), 0);  // cores never come within 1 nm (contact gap 2 um)
  for (std::size_t i = 0; i < p.grains.size(); ++i) EXPECT_EQ(kept.grains[i].colour, p.grains[i].colour);
  EXPECT_EQ(separate_colours_within(p, reach), before);
  for (auto [i, j] : core_pairs(p, reach)) EXPECT_NE(p.grains[i].colour, p.grains[j].colour) << i << " " << j;
  for (auto [i, j] : contact_pairs(p)) EXPECT_NE(p.grains[i].colour, p.grains[j].colour) << i << " " << j;
  EXPECT_GT(p.stats.colours, paper_packing().stats.colours);
  EXPECT_LE(p.stats.colours, 12);
  std::printf("colours at the 20 um reach: %d (packing: %d), %d pairs re-coloured\n", p.stats.colours,
              paper_packing().stats.colours, before);
}

TEST(Packing, SameSeedGivesByteIdenticalFilesAndReadsBack) {
  const auto dir = std::filesystem::temp_directory_path() / ("pbx_test_packing_" + std::to_string(::getpid()));
  std::filesystem::remove_all(dir);
  write_packing(paper_packing(), (dir / "a").string());
  write_packing(generate_packing(spec_from(kDeck)), (dir / "b").string());
  for (const char* f : {"packing.csv", "packing.json", "packing.png"})
    EXPECT_EQ(slurp(dir / "a" / f), slurp(dir / "b" / f)) << f;
  const Packing q = read_packing((dir / "a").string());
  ASSERT_EQ(q.grains.size(), paper_packing().grains.size());
  for (std::size_t i = 0; i < q.grains.size(); ++i) {
    EXPECT_EQ(q.grains[i].centre, paper_packing().grains[i].centre);
    EXPECT_EQ(q.grains[i].coat, paper_packing().grains[i].coat);
    EXPECT_EQ(q.grains[i].colour, paper_packing().grains[i].colour);
  }
  EXPECT_NEAR(q.stats.porosity, paper_packing().stats.porosity, 1e-12);
  // A different seed gives a different packing.
  const Packing other = generate_packing(spec_from(replace(kDeck, "seed = 3", "seed = 4")));
  EXPECT_NE(other.grains[0].centre, paper_packing().grains[0].centre);
  std::filesystem::remove_all(dir);
}

namespace {
// Whether `text`, drawn in black at `scale`, appears in `img` with its cell's top row between rows
// y0 and y1: every pixel of the glyphs black there and every other pixel of the cell not black.
bool shows_text(const RgbImage& img, int y0, int y1, const std::string& text, int scale) {
  RgbImage t;
  t.width = text_width(text, scale);
  t.height = kGlyphRows * scale;
  t.rgb.assign(static_cast<std::size_t>(t.width) * t.height * 3, 255);
  const std::uint8_t black[3] = {0, 0, 0};
  draw_text(t, 0, 0, text, scale, black);
  const auto is_black = [](const RgbImage& im, int i, int j) {
    const std::uint8_t* c = &im.rgb[3 * (static_cast<std::size_t>(j) * im.width + i)];
    return c[0] == 0 && c[1] == 0 && c[2] == 0;
  };
  for (int y = y0; y <= y1 && y + t.height <= img.height; ++y)
    for (int x = 0; x + t.width <= img.width; ++x) {
      bool same = true;
      for (int j = 0; j < t.height && same; ++j)
        for (int i = 0; i < t.width && same; ++i) same = is_black(t, i, j) == is_black(img, x + i, y + j);
      if (same) return true;
    }
  return false;
}
}  // namespace

// packing.png: the box at 1200 px on its long side, then a white strip with a scale bar labelled
// with its length and a legend of the three phases (their swatches in the picture's colours, their
// names written), as docs/deck/microstructure.md says. Without the label or the legend this fails.
TEST(Packing, PictureHasALabelledScaleBarAndALegend) {
  const auto dir = std::filesystem::temp_directory_path() / ("pbx_test_picture_" + std::to_string(::getpid()));
  std::filesystem::remove_all(dir);
  const Packing& p = paper_packing();
  write_packing(p, dir.string());
  const RgbImage img = read_png((dir / "packing.png").string());
  const double px = p.box.maxCoeff() / 1200.0;  // 1.2 mm box: 1 px = 1 um
  const int box_h = static_cast<int>(std::lround(p.box.y() / px));
  ASSERT_EQ(img.width, std::lround(p.box.x() / px));
  ASSERT_GT(img.height, box_h + 30);
  const auto rgb = [&](int i, int j) { return &img.rgb[3 * (static_cast<std::size_t>(j) * img.width + i)]; };
  const auto is = [&](int i, int j, std::uint8_t r, std::uint8_t g, std::uint8_t b) {
    return rgb(i, j)[0] == r && rgb(i, j)[1] == g && rgb(i, j)[2] == b;
  };
  // the bar: 100 um (the largest 1-2-5 length within 15 % of the 1 mm width), 8 px thick, from
  // x = 20 and 17 px below the box, then white before its label
  for (int j = box_h + 17; j < box_h + 25; ++j) {
    EXPECT_TRUE(is(19, j, 255, 255, 255)) << j;
    int run = 0;
    while (is(20 + run, j, 0, 0, 0)) ++run;
    EXPECT_EQ(run, std::lround(100e-6 / px)) << "row " << j;
  }
  EXPECT_TRUE(is(20, box_h + 16, 255, 255, 255));
  EXPECT_TRUE(is(20, box_h + 25, 255, 255, 255));
  // its length written 10 px to its right, the text cell from 12 px below the box
  EXPECT_TRUE(shows_text(img, box_h + 12, box_h + 12, "100 \u00b5m", 2));
  EXPECT_FALSE(shows_text(img, box_h + 12, box_h + 12, "200 \u00b5m", 2));  // the check tells texts apart
  // the legend: each phase named, and swatches in the binder's dark green and the first grain tint
  for (const char* label : {"TATB grain (tinted by colour)", "binder coat (dark green)", "pore (white)"}) {
    EXPECT_TRUE(shows_text(img, box_h, img.height - 1, label, 2)) << label;
  }
  int green = 0, tint = 0;
  for (int j = box_h; j < img.height; ++j)
    for (int i = 0; i < img.width; ++i) {
      green += is(i, j, 30, 90, 40);
      tint += is(i, j, 240, 200, 60);
    }
  EXPECT_EQ(green, 16 * 16);  // the swatch's inside (18 px with a 1 px black rim)
  EXPECT_GT(tint, 0);
  const std::string json = slurp(dir / "packing.json");
  EXPECT_NE(json.find("bar below the box is 100 um long"), std::string::npos);
  EXPECT_NE(json.find("\"scale_bar_um\": 100"), std::string::npos) << json;
  std::filesystem::remove_all(dir);
}

// The font writes what the picture needs, and says which character it lacks instead of skipping it.
TEST(BitmapText, WritesDigitsLettersAndMicroAndNamesAMissingGlyph) {
  EXPECT_TRUE(font_has("0123456789 \u00b5m (),.:-"));
  EXPECT_EQ(text_width("100 \u00b5m", 2), 6 * 6 * 2);  // µ is one character of two UTF-8 bytes
  EXPECT_FALSE(font_has("Q"));
  try {
    text_width("Quartz", 1);
    FAIL();
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("U+0051"), std::string::npos) << e.what();
  }
  // "1" at scale 1: its column 2 set in rows 0-6 (the stem), nothing in the descender rows
  RgbImage img;
  img.width = 6, img.height = kGlyphRows;
  img.rgb.assign(6 * kGlyphRows * 3, 255);
  const std::uint8_t black[3] = {0, 0, 0};
  draw_text(img, 0, 0, "1", 1, black);
  for (int j = 0; j < kGlyphRows; ++j) EXPECT_EQ(img.rgb[3 * (j * 6 + 2)], j < 7 ? 0 : 255) << j;
}

TEST(Packing, DensityTargetIsConvertedWithTheTmd) {
  const PackingSpec s = spec_from(replace(kDeck, "porosity = 0.0932", "density = \"1.7575 g/cm3\""));
  EXPECT_NEAR(s.porosity, 1 - 1757.5 / s.tmd(), 1e-12);
}

TEST(Packing, BadDecksNameTheKey) {
  auto msg = [](const std::string& text) {
    try {
      spec_from(text);
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  EXPECT_NE(msg(replace(kDeck, "diameter_min = \"50 um\"", "diameter_min = \"400 um\"")).find("packing.diameter_min"),
            std::string::npos);
  EXPECT_NE(msg(replace(kDeck, "porosity = 0.0932", "porosity = 1.0")).find("packing.porosity: must lie in [0, 1)"),
            std::string::npos);
  EXPECT_NE(msg(replace(kDeck, "porosity = 0.0932", "porosity = -0.01")).find("packing.porosity"), std::string::npos);
  EXPECT_NE(msg(replace(kDeck, "mass_ratio = [95, 5]", "mass_ratio = [95, 0]")).find("packing.mass_ratio"),
            std::string::npos);
  EXPECT_NE(msg(replace(kDeck, "mass_ratio = [95, 5]", "mass_ratio = [-95, 5]")).find("packing.mass_ratio"),
            std::string::npos);
  EXPECT_NE(msg(replace(kDeck, "share = 0.25", "share = 0.5")).find("share"), std::string::npos);
  EXPECT_NE(msg(replace(kDeck, "seed = 3", "seed = 3\ncoat = \"thick\"")).find("packing.coat"), std::string::npos);
  EXPECT_NE(msg(replace(kDeck, "seed = 3", "seed = 3\nsede = 4")).find("unknown key 'packing.sede'"),
            std::string::npos);
  // a box that would need more grains than the packer can place in reasonable time (it used to run
  // for hours or out of memory)
  EXPECT_NE(msg(replace(kDeck, "box = [\"1.0 mm\", \"1.2 mm\"]", "box = [\"10 cm\", \"10 cm\"]"))
                .find("packing.diameter_min: the 0.1 x 0.1 m box could need up to"),
            std::string::npos)
      << msg(replace(kDeck, "box = [\"1.0 mm\", \"1.2 mm\"]", "box = [\"10 cm\", \"10 cm\"]"));
  EXPECT_NE(msg(replace(kDeck, "box = [\"1.0 mm\", \"1.2 mm\"]", "box = [\"1.0 mm\", inf]"))
                .find("packing.box: entry 1 must be a finite number"),
            std::string::npos);
}

// A packing folder edited by hand (or corrupted) is read strictly: a cell that is not wholly a
// number, or a grain centre outside the box, is an error naming the file and line or grain.
TEST(Packing, EditedPackingFileIsReadStrictly) {
  const auto dir = std::filesystem::temp_directory_path() / ("pbx_test_packing_edit_" + std::to_string(::getpid()));
  std::filesystem::remove_all(dir);
  write_packing(paper_packing(), dir.string());
  const std::string csv = slurp(dir / "packing.csv");
  const auto header = csv.find("grain,x_m,y_m,diameter_m,coat_m,colour,mode\n");
  ASSERT_NE(header, std::string::npos);
  const auto row = header + std::string("grain,x_m,y_m,diameter_m,coat_m,colour,mode\n").size();
  const auto comma = csv.find(',', row);  // the first grain's x cell starts after it
  const auto next = csv.find(',', comma + 1);
  auto read_with_x = [&](const std::string& x) {
    std::ofstream(dir / "packing.csv") << csv.substr(0, comma + 1) + x + csv.substr(next);
    try {
      read_packing(dir.string());
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("(no error)");
  };
  EXPECT_NE(read_with_x("0.01").find("grain 0 at (0.01"), std::string::npos) << read_with_x("0.01");
  EXPECT_NE(read_with_x("0.0004abc").find("'0.0004abc' is not a finite number"), std::string::npos)
      << read_with_x("0.0004abc");
  EXPECT_NE(read_with_x("nan").find("'nan' is not a finite number"), std::string::npos) << read_with_x("nan");
  // A grain of diameter 1e300 m passed the position check for any centre; a row pasted twice
  // stacked two cores in one place. Both are refused naming the line.
  auto read_text = [&](const std::string& text) {
    std::ofstream(dir / "packing.csv") << text;
    try {
      read_packing(dir.string());
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("(no error)");
  };
  const auto row_end = csv.find('\n', row);
  const std::string first = csv.substr(row, row_end + 1 - row);  // "0,x,y,d,coat,colour,mode\n"
  std::string huge = first;
  {
    std::size_t c = 0;
    for (int k = 0; k < 3; ++k) c = huge.find(',', c) + 1;  // the diameter cell
    huge.replace(c, huge.find(',', c) - c, "1e300");
  }
  const int line = static_cast<int>(std::count(csv.begin(), csv.begin() + static_cast<long>(row), '\n')) + 1;
  const std::string big = read_text(csv.substr(0, row) + huge + csv.substr(row_end + 1));
  EXPECT_NE(big.find(fmt::format("packing.csv:{}: grain 0 has diameter 1e+300 m", line)), std::string::npos) << big;
  const std::string dup = read_text(csv + first);
  EXPECT_NE(dup.find("has the centre of grain 0 (line " + std::to_string(line) + "): a duplicated row?"),
            std::string::npos)
      << dup;
  EXPECT_EQ(read_text(csv), "(no error)");
  std::filesystem::remove_all(dir);
}

TEST(Packing, UnreachablePorosityStatesTheBestReached) {
  const std::string m =
      error_of(replace(replace(kDeck, "porosity = 0.0932", "porosity = 0.02"), "seed = 3", "seed = 3\nattempts = 1"));
  EXPECT_NE(m.find("cannot be reached"), std::string::npos) << m;
  EXPECT_NE(m.find("densest overlap-free packing found has porosity"), std::string::npos) << m;
}

TEST(Packing, WallsKeepGrainsInsideAndTheMassBalanceExact) {
  const Packing p = generate_packing(spec_from(
      replace(replace(kDeck, "porosity = 0.0932", "porosity = 0.25"), "seed = 3", "seed = 3\nboundary = \"walls\"")));
  EXPECT_FALSE(p.periodic);
  for (const auto& g : p.grains)
    for (int k = 0; k < 2; ++k) {
      EXPECT_GE(g.centre[k], 0.5 * g.diameter);
      EXPECT_LE(g.centre[k], p.box[k] - 0.5 * g.diameter);
    }
  // Coats cut by the walls are accounted for: the ratio is still exact.
  EXPECT_NEAR(p.stats.tatb_mass_fraction, 0.95, 1e-9);
  EXPECT_NEAR(p.stats.porosity, 0.25, 0.002);
}

TEST(Packing, ExampleDecksAreValid) {
  for (const char* f : {"porosity_0.0932.toml", "porosity_0.0798.toml", "porosity_0.08.toml", "porosity_0.053.toml"}) {
    Deck d = Deck::from_file(std::string(PBXMPM_EXAMPLES_DIR "/packing/") + f);
    const PackingSpec s = read_packing_spec(d.root().table("packing"));
    EXPECT_NO_THROW(d.check_unused()) << f;
    EXPECT_NEAR(s.tmd(), 1938.126, 0.001) << f;
  }
}

TEST(Packing, PackedDiametersPassKsPerMode) {
  // The grains of the generated specimen itself (not only the sampler) against each requested mode.
  const Packing& p = paper_packing();
  const PackingSpec s = spec_from(kDeck);
  for (int k = 0; k < 2; ++k) {
    std::vector<double> d;
    for (const auto& g : p.grains)
      if (g.mode == k) d.push_back(g.diameter);
    std::sort(d.begin(), d.end());
    double D = 0;
    const double n = static_cast<double>(d.size());
    for (std::size_t i = 0; i < d.size(); ++i) {
      const double f = s.sizes.mode_cdf(k, d[i]);
      D = std::max({D, (i + 1) / n - f, f - i / n});
    }
    EXPECT_LT(D, 1.628 / std::sqrt(n)) << "mode " << k << ", n = " << n;  // KS, 1 % level
  }
}

TEST(Packing, DensestPaperSpecimenWithThePapersGrainSizes) {
  // Porosity 0.053 needs a TATB area fraction of 0.9016 with grains in [50, 300] um (issue 5).
  Deck d = Deck::from_file(PBXMPM_EXAMPLES_DIR "/packing/porosity_0.053.toml");
  const PackingSpec s = read_packing_spec(d.root().table("packing"));
  EXPECT_NEAR(s.sizes.dmin, 50e-6, 1e-12);
  EXPECT_NEAR(s.sizes.dmax, 300e-6, 1e-12);
  const Packing p = generate_packing(s);
  EXPECT_NEAR(p.stats.porosity, 0.053, 0.002);
  EXPECT_GT(p.stats.tatb_area_fraction + p.stats.binder_area_fraction, 0.945);
  EXPECT_NEAR(p.stats.tatb_mass_fraction, 0.95, 1e-9);
  for (std::size_t i = 0; i < p.grains.size(); ++i) {
    const Grain& a = p.grains[i];
    EXPECT_TRUE(a.diameter >= s.sizes.dmin && a.diameter <= s.sizes.dmax) << a.diameter;
    for (std::size_t j = i + 1; j < p.grains.size(); ++j) {
      const Grain& b = p.grains[j];
      Eigen::Vector2d dx = b.centre - a.centre;
      for (int k = 0; k < 2; ++k) dx[k] -= p.box[k] * std::round(dx[k] / p.box[k]);
      EXPECT_GE(dx.norm(), 0.5 * (a.diameter + b.diameter)) << i << " " << j;
    }
  }
  // The fine grains (at most 1 % shrunk) still follow their requested mode: KS at the 1 % level.
  std::vector<double> fine;
  for (const auto& g : p.grains)
    if (g.mode == 1) fine.push_back(g.diameter);
  std::sort(fine.begin(), fine.end());
  const double n = static_cast<double>(fine.size());
  ASSERT_GT(n, 30);
  double D = 0;
  for (std::size_t i = 0; i < fine.size(); ++i) {
    const double f = s.sizes.mode_cdf(1, fine[i]);
    D = std::max({D, (i + 1) / n - f, f - i / n});
  }
  EXPECT_LT(D, 1.628 / std::sqrt(n));
}

// packing.tiles: copies of the periodic cell side by side (a weak-scaling specimen: the same work
// per rank). Each copy is the cell shifted by whole periods, the porosity and mass balance are the
// cell's, and every contact of the cell, across its periodic edges included, appears once per
// copy with its two colours different: the copies meet along the seams as the cell meets its
// periodic images.
TEST(Packing, TilesRepeatThePeriodicCellAcrossItsEdges) {
  const Packing& cell = paper_packing();
  const Packing p = generate_packing(spec_from(replace(kDeck, "seed = 3", "seed = 3\ntiles = [2, 3]")));
  const std::size_t n = cell.grains.size();
  ASSERT_EQ(p.grains.size(), 6 * n);
  EXPECT_EQ(p.box.x(), 2 * cell.box.x());
  EXPECT_EQ(p.box.y(), 3 * cell.box.y());
  EXPECT_EQ(p.tiles[0], 2);
  EXPECT_EQ(p.tiles[1], 3);
  for (int j = 0; j < 3; ++j)
    for (int i = 0; i < 2; ++i)
      for (std::size_t g = 0; g < n; ++g) {
        const Grain& a = p.grains[static_cast<std::size_t>(j * 2 + i) * n + g];
        const Grain& b = cell.grains[g];
        EXPECT_EQ(a.centre.x(), b.centre.x() + i * cell.box.x());
        EXPECT_EQ(a.centre.y(), b.centre.y() + j * cell.box.y());
        EXPECT_EQ(a.diameter, b.diameter);
        EXPECT_EQ(a.coat, b.coat);
        EXPECT_EQ(a.colour, b.colour);
      }
  EXPECT_NEAR(p.stats.porosity, cell.stats.porosity, 1e-9);
  EXPECT_NEAR(p.stats.tatb_mass_fraction, 0.95, 1e-9);
  const auto pairs = contact_pairs(p);
  EXPECT_EQ(pairs.size(), 6 * contact_pairs(cell).size());
  for (auto [i, j] : pairs) EXPECT_NE(p.grains[i].colour, p.grains[j].colour) << i << " " << j;
  EXPECT_EQ(p.stats.colours, cell.stats.colours);
}

TEST(Packing, TilesNeedAPeriodicCellAndWholeCounts) {
  auto msg = [](const std::string& text) {
    try {
      generate_packing(spec_from(text));
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  const auto with = [](const std::string& extra) { return replace(kDeck, "seed = 3", "seed = 3\n" + extra); };
  EXPECT_NE(msg(with("tiles = [0, 1]")).find("packing.tiles: entry 0 must be a whole number in [1, 64] (got 0)"),
            std::string::npos)
      << msg(with("tiles = [0, 1]"));
  EXPECT_NE(msg(with("tiles = [2, 1.5]")).find("packing.tiles: entry 1 must be a whole number"), std::string::npos);
  EXPECT_NE(msg(with("tiles = [2]")).find("packing.tiles: expected [copies along x, copies along y]"),
            std::string::npos);
  EXPECT_NE(msg(replace(with("tiles = [2, 1]\nboundary = \"walls\""), "porosity = 0.0932", "porosity = 0.25"))
                .find("packing.tiles: needs boundary = \"periodic\""),
            std::string::npos);
  Packing walls = paper_packing();
  walls.periodic = false;
  EXPECT_THROW(tile_packing(walls, {2, 1}), InputError);
  // one copy is the cell itself
  const Packing one = generate_packing(spec_from(with("tiles = [1, 1]")));
  ASSERT_EQ(one.grains.size(), paper_packing().grains.size());
  for (std::size_t g = 0; g < one.grains.size(); ++g) EXPECT_EQ(one.grains[g].centre, paper_packing().grains[g].centre);
}
