// A simulation built from a segmented image, end to end through the binary (issue 29: "a
// simulation built from an imported image" was never run): `pbxmpm pack --from-image` turns a
// 200 x 100 px image at 2 um (three TATB disks of 40 um radius, two of them 2 um apart, one round
// pore, binder elsewhere) into a packing, and `pbxmpm run` compresses it in the die. Independent
// expected values: the image's own pixel counts. The particles' phase areas must match the pixel
// areas within the sampling error of a 5 um particle spacing on a 40 um radius (a one-sided bias
// of half a spacing on the perimeter would be 2 x 2.5/40 = 12 %; the 1 % bound asks for an
// unbiased sampling; measured 0.12 % and 0.17 %), the porosity within 0.003 (measured 0.0012),
// and the two close grains must be two bodies in Coulomb contact that carries load.
#include <cmath>

#include <gtest/gtest.h>

#include "analysis/csv_table.hpp"
#include "binary_test.hpp"
#include "io/json.hpp"
#include "microstructure/png_image.hpp"

using namespace pbx;

namespace {
class ImageRun : public pbx::test::BinaryTest {
 protected:
  ImageRun() : BinaryTest("pbx_test_image_run_") {}
};
}  // namespace

TEST_F(ImageRun, ASegmentedImageIsPackedAndCompressedWithItsPhaseAreas) {
  RgbImage img;
  img.width = 200;
  img.height = 100;
  img.rgb.assign(200 * 100 * 3, 0);  // binder everywhere but the grains and one pore
  const double c[3][2] = {{40, 50}, {81, 50}, {150, 40}};
  long tatb_px = 0, void_px = 0;
  for (int y = 0; y < 100; ++y)
    for (int x = 0; x < 200; ++x) {
      int phase = 1;
      for (auto& q : c)
        if ((x + 0.5 - q[0]) * (x + 0.5 - q[0]) + (y + 0.5 - q[1]) * (y + 0.5 - q[1]) < 20 * 20) phase = 0;
      if ((x + 0.5 - 120) * (x + 0.5 - 120) + (y + 0.5 - 75) * (y + 0.5 - 75) < 12 * 12) phase = 2;
      std::uint8_t* p = &img.rgb[3 * (y * 200 + x)];
      if (phase == 0) p[0] = 255, p[1] = 255, p[2] = 0, ++tatb_px;
      if (phase == 1) p[1] = 128;
      if (phase == 2) p[0] = 255, p[1] = 255, p[2] = 255, ++void_px;
    }
  const long binder_px = 20000 - tatb_px - void_px;
  write_png((dir / "seg.png").string(), img);
  const double px = 2e-6;  // m
  const std::string deck = write("run.toml", R"([run]
end_strain = 0.002
history_points = 20
snapshots = 0
[grid]
cell_size = "10 um"
[solver]
mass_scaling = 100
[die]
width = "0.4 mm"
height = "0.2 mm"
punch_velocity = "0.3 m/s"
ramp_strain = 0.0005
[materials.tatb]
model = "linear_elastic"
density = "1.934 g/cm3"
bulk_modulus = "10.59 GPa"
shear_modulus = "11.5 GPa"
[materials.binder]
model = "linear_elastic"
density = "2.02 g/cm3"
youngs_modulus = "1 GPa"
poisson_ratio = 0.4
[specimen]
grain_material = "tatb"
binder_material = "binder"
packing_dir = "pack"
[contact]
default = "coulomb"
friction = 0.3
)");
  // the image's own deck (a run deck with specimen.packing_dir takes no [packing])
  const std::string pack_deck = write("pack.toml", "[packing]\npixel_size = \"2 um\"\ncontact_gap = \"2 um\"\n");
  const auto pack = test::pbxmpm(
      fmt::format("pack {} --from-image {} --out {}", pack_deck, (dir / "seg.png").string(), (dir / "pack").string()));
  ASSERT_EQ(pack.code, 0) << pack.output;
  const auto run = test::pbxmpm(fmt::format("run {} --out {} -q", deck, (dir / "out").string()));
  ASSERT_EQ(run.code, 0) << run.output;

  const Json rj = json_read_file((dir / "out" / "run.json").string());
  EXPECT_EQ(json_string(*json_find(rj, "status")), "finished");
  // where the wall time went: every stage of a multi-field die run did work, and the stages
  // plus the rest of the run make up the wall time the run reports (one segment)
  const Json& stages = *json_find(rj, "stage_wall_s");
  double stage_sum = 0;
  for (const char* s : {"rigid_p2g", "reset", "p2g", "contact", "grid_update", "g2p", "stress", "bodies"}) {
    const double w = json_number(*json_find(stages, s));
    EXPECT_GE(w, 0.0) << s;
    if (std::string(s) != "bodies") {
      EXPECT_GT(w, 0.0) << s;
    }
    stage_sum += w;
  }
  const double wall = json_number(*json_find(rj, "wall_time_s"));
  EXPECT_NEAR(stage_sum + json_number(*json_find(stages, "outside_steps")), wall, 0.01 * wall + 1e-3);
  const double box = 0.4e-3 * 0.2e-3;
  const Json& spec = *json_find(rj, "specimen");
  EXPECT_NEAR(json_number(*json_find(spec, "packing_porosity")), void_px / 20000.0, 1e-12);
  EXPECT_NEAR(json_number(*json_find(spec, "porosity")), void_px / 20000.0, 0.003);
  // each phase's particle area against its pixel area (particles x (h/2)^2, 2 per cell and axis)
  double tatb_area = 0, binder_area = 0;
  for (const Json& m : json_array(*json_find(rj, "materials"))) {
    const double area = json_number(*json_find(m, "particles")) * 5e-6 * 5e-6;
    (json_string(*json_find(m, "name")) == "tatb" ? tatb_area : binder_area) += area;
  }
  EXPECT_NEAR(tatb_area / (tatb_px * px * px), 1.0, 0.01);
  EXPECT_NEAR(binder_area / (binder_px * px * px), 1.0, 0.01);
  EXPECT_GT(box, tatb_area + binder_area);
  // the two touching grains are two bodies: Coulomb contact between TATB fields carried load
  const CsvTable h = CsvTable::read((dir / "out" / "history.csv").string());
  const auto& fn = h.numbers("contact_tatb_tatb_fn_N_per_m");
  EXPECT_GT(fn.back(), 0.0);
  EXPECT_GT(h.numbers("punch_stress_Pa").back(), 0.0);
}
