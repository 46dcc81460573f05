// Segmented-image import: phase areas, grains as connected components, colouring.
#include <filesystem>

#include <unistd.h>

#include <gtest/gtest.h>

#include "core/error.hpp"
#include "io/deck.hpp"
#include "microstructure/colouring.hpp"
#include "microstructure/image_import.hpp"
#include "microstructure/png_image.hpp"
#include "microstructure/rasterise.hpp"

using namespace pbx;

namespace {

// 200 x 100 px: three TATB disks (two touching), binder rings, void elsewhere.
std::string make_image(const std::filesystem::path& dir, long& tatb_px, long& binder_px) {
  RgbImage img;
  img.width = 200;
  img.height = 100;
  img.rgb.assign(200 * 100 * 3, 255);
  const double c[3][2] = {{40, 50}, {81, 50}, {150, 40}};
  tatb_px = binder_px = 0;
  for (int y = 0; y < 100; ++y)
    for (int x = 0; x < 200; ++x) {
      int phase = 2;
      for (auto& q : c) {
        const double r2 = (x + 0.5 - q[0]) * (x + 0.5 - q[0]) + (y + 0.5 - q[1]) * (y + 0.5 - q[1]);
        if (r2 < 20 * 20)
          phase = 0;
        else if (r2 < 24 * 24 && phase != 0)
          phase = 1;
      }
      std::uint8_t* p = &img.rgb[3 * (y * 200 + x)];
      if (phase == 0) p[0] = 255, p[1] = 255, p[2] = 0, ++tatb_px;
      if (phase == 1) p[0] = 0, p[1] = 128, p[2] = 0, ++binder_px;
    }
  std::filesystem::create_directories(dir);
  const auto f = (dir / "seg.png").string();
  write_png(f, img);
  return f;
}

}  // namespace

TEST(ImageImport, PhaseFractionsGrainsAndColours) {
  const auto dir = std::filesystem::temp_directory_path() / ("pbx_test_image_" + std::to_string(::getpid()));
  long tatb = 0, binder = 0;
  const std::string file = make_image(dir, tatb, binder);
  Deck d = Deck::from_string(
      "[packing]\npixel_size = \"2 um\"\ncontact_gap = \"2 um\"\n[packing.legend]\ntatb = \"#FFFF00\"\nbinder = "
      "\"#008000\"\nvoid = \"#FFFFFF\"\n",
      "img.toml");
  const Packing p = import_image(read_image_spec(d.root().table("packing"), file));
  d.check_unused();
  ASSERT_EQ(p.grains.size(), 3u);
  EXPECT_NEAR(p.stats.tatb_area_fraction, tatb / 20000.0, 1e-12);
  EXPECT_NEAR(p.stats.binder_area_fraction, binder / 20000.0, 1e-12);
  EXPECT_NEAR(p.box.x(), 400e-6, 1e-18);
  // Grains 0 and 1 are 1 px (2 um) apart, within the contact gap: different colours.
  for (auto& g : p.grains) EXPECT_NEAR(g.diameter, 80e-6, 2e-6);
  EXPECT_NE(p.grains[0].colour, p.grains[1].colour);
  // Particles at 1 um sub-cells reproduce the phase area fractions to 0.5 %.
  const auto r = raster_report(rasterise(p, 2e-6, 2, {0, 0}), p.box, 1934, 2020);
  EXPECT_NEAR((1 - r.porosity) / (1 - p.stats.porosity), 1.0, 0.005);
  EXPECT_NEAR(double(r.tatb_particles) / r.particles, double(tatb) / (tatb + binder), 0.005);
  // Round trip through the output folder.
  write_packing(p, (dir / "out").string());
  const Packing q = read_packing((dir / "out").string());
  EXPECT_EQ(q.image.label, p.image.label);
  EXPECT_NEAR(q.stats.porosity, p.stats.porosity, 1e-12);
  std::filesystem::remove_all(dir);
}

TEST(ImageImport, ColourNotInLegendIsAnInputError) {
  const auto dir = std::filesystem::temp_directory_path() / ("pbx_test_image2_" + std::to_string(::getpid()));
  long t = 0, b = 0;
  const std::string file = make_image(dir, t, b);
  Deck d = Deck::from_string("[packing]\npixel_size = \"2 um\"\n[packing.legend]\ntatb = \"#FF0000\"\n", "img.toml");
  EXPECT_THROW(import_image(read_image_spec(d.root().table("packing"), file)), InputError);
  Deck bad = Deck::from_string("[packing]\npixel_size = \"2 um\"\n[packing.legend]\ntatb = \"yellow\"\n", "img.toml");
  EXPECT_THROW(read_image_spec(bad.root().table("packing"), file), InputError);
  std::filesystem::remove_all(dir);
}

// An image without a single TATB pixel has no grain to simulate, and a contact gap of hundreds of
// pixels (a unit slip) would make the colouring search run for hours: both are input errors.
// The legend table is optional.
TEST(ImageImport, NoTatbOrAHugeContactGapIsAnInputError) {
  const auto dir = std::filesystem::temp_directory_path() / ("pbx_test_image3_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  RgbImage white;
  white.width = 10;
  white.height = 10;
  white.rgb.assign(10 * 10 * 3, 255);
  const std::string blank = (dir / "blank.png").string();
  write_png(blank, white);
  const std::string legend = "[packing.legend]\ntatb = \"#FFFF00\"\nbinder = \"#008000\"\nvoid = \"#FFFFFF\"\n";
  auto error_of = [&](const std::string& deck_text, const std::string& file) {
    Deck d = Deck::from_string(deck_text, "img.toml");
    try {
      import_image(read_image_spec(d.root().table("packing"), file));
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("(no error)");
  };
  const std::string none = error_of("[packing]\npixel_size = \"2 um\"\n" + legend, blank);
  EXPECT_NE(none.find("no pixel has the TATB colour #FFFF00"), std::string::npos) << none;
  long t = 0, b = 0;
  const std::string file = make_image(dir, t, b);
  const std::string gap = error_of("[packing]\npixel_size = \"2 um\"\ncontact_gap = \"1 mm\"\n" + legend, file);
  EXPECT_NE(gap.find("contact_gap = 0.001 m spans 500 pixels"), std::string::npos) << gap;
  // without a [packing.legend] the documented default colours apply (it used to be required)
  EXPECT_EQ(error_of("[packing]\npixel_size = \"2 um\"\n", file), "(no error)");
  std::filesystem::remove_all(dir);
}
