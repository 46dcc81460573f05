// The 3-D path end to end: `pbxmpm check` and `pbxmpm run` on a deck with run.dimension = 3
// (examples/3d/confined_cube.toml: a linear-elastic cube in uniaxial strain between six rigid
// bodies), checked against the closed form sigma_yy = M eps, sigma_xx = sigma_zz = lambda eps with
// M = E (1 - nu)/((1 + nu)(1 - 2 nu)) = 120 Pa and lambda = E nu/((1 + nu)(1 - 2 nu)) = 40 Pa. A 3-D
// law that dropped the z direction or used the plane-strain form would change lambda/M (1/3 here)
// or szz; units without "per metre of depth" and the dimension in run.json are asserted too.
#include <cmath>
#include <filesystem>

#include <gtest/gtest.h>

#include "analysis/csv_table.hpp"
#include "binary_test.hpp"
#include "io/json.hpp"

using namespace pbx;

namespace {
class ThreeD : public pbx::test::BinaryTest {
 protected:
  ThreeD() : BinaryTest("pbx_test_3d_") {}
};
const std::string kDeck = std::string(PBXMPM_EXAMPLES_DIR) + "/3d/confined_cube.toml";
}  // namespace

TEST_F(ThreeD, ConfinedCubeGivesTheUniaxialStrainStresses) {
  const auto check = test::pbxmpm("check " + kDeck);
  ASSERT_EQ(check.code, 0) << check.output;
  EXPECT_NE(check.output.find("valid 3-D deck. 8000 particles"), std::string::npos) << check.output;
  EXPECT_NE(check.output.find("grid 17 x 18 x 17 nodes"), std::string::npos) << check.output;

  const auto run = test::pbxmpm(fmt::format("run {} --out '{}' -q", kDeck, (dir / "cube").string()));
  ASSERT_EQ(run.code, 0) << run.output;
  const Json rj = json_read_file((dir / "cube" / "run.json").string());
  EXPECT_EQ(json_number(*json_find(rj, "dimension")), 3);
  EXPECT_EQ(json_string(*json_find(rj, "units")), "SI; 3-D");

  const CsvTable h = CsvTable::read((dir / "cube" / "history.csv").string());
  ASSERT_FALSE(h.has("kinetic_J_per_m")) << "3-D energies are totals, not per metre of depth";
  const auto& t = h.numbers("t_s");
  const auto &sxx = h.numbers("sxx_Pa"), &syy = h.numbers("syy_Pa"), &szz = h.numbers("szz_Pa");
  const auto &left = h.numbers("left_fx_N"), &back = h.numbers("back_fz_N"), &top = h.numbers("top_fy_N");
  const double E = 100, nu = 0.25, M = E * (1 - nu) / ((1 + nu) * (1 - 2 * nu)),
               lambda = E * nu / ((1 + nu) * (1 - 2 * nu));
  const double v = 0.01, t_ramp = 0.1;  // the top plate's speed after its linear ramp (the deck's)
  auto strain = [&](double s) { return s < t_ramp ? 0.5 * v * s * s / t_ramp : v * (s - t_ramp) + 0.5 * v * t_ramp; };
  const std::size_t last = t.size() - 1;
  // volume-averaged stresses at the end (0.5 % strain; KE/IE has settled to about 1 %)
  const double eps = strain(t[last]);
  EXPECT_NEAR(-syy[last] / (M * eps), 1.0, 0.02);
  EXPECT_NEAR(sxx[last] / syy[last], lambda / M, 0.005);
  EXPECT_NEAR(szz[last] / syy[last], lambda / M, 0.005);
  // reactions over the second half (the plate force rings with the cube's reverberation; its mean
  // does not): side walls carry lambda eps over their 1 m^2, the plate M eps
  double wall = 0, plate = 0, expect_wall = 0, expect_plate = 0;
  for (std::size_t i = last / 2; i <= last; ++i) {
    wall += left[i];
    plate += -top[i];
    expect_wall += lambda * strain(t[i]);
    expect_plate += M * strain(t[i]);
    EXPECT_NEAR(left[i], back[i], 1e-9 * std::abs(left[i]) + 1e-15) << "x and z walls of a cube differ at row " << i;
  }
  EXPECT_NEAR(wall / expect_wall, 1.0, 0.03);
  EXPECT_NEAR(plate / expect_plate, 1.0, 0.05);
}

// A study runs 3-D decks as it runs 2-D ones (since 2026-12-06; it refused them before): both runs
// of the cube finish, the stiffer cube ends with twice the stress (linear elasticity, the same
// plate motion), and the report is written.
TEST_F(ThreeD, AStudyRunsThreeDimensionalDecks) {
  const std::string study = write("study.toml", fmt::format(R"([study]
name = "cube"
base = "{}"
[[study.group]]
name = "modulus"
key = "materials.cube.youngs_modulus"
values = [100.0, 200.0]
)",
                                                            kDeck));
  const auto r = test::pbxmpm(fmt::format("study {} --out '{}' --threads 1 --quiet", study, (dir / "out").string()));
  ASSERT_EQ(r.code, 0) << r.output;
  std::vector<double> syy[2];
  for (int k = 0; k < 2; ++k) {
    const std::filesystem::path run = dir / "out" / "runs" / (k == 0 ? "modulus-100-s1" : "modulus-200-s1");
    const Json rj = json_read_file((run / "run.json").string());
    const Json* status = json_find(rj, "status");
    ASSERT_NE(status, nullptr) << run;
    EXPECT_EQ(json_string(*status), "finished") << run;
    syy[k] = CsvTable::read((run / "history.csv").string()).numbers("syy_Pa");
  }
  ASSERT_EQ(syy[0].size(), syy[1].size());
  ASSERT_GT(syy[0].size(), 10u);
  EXPECT_NEAR(syy[1].back() / syy[0].back(), 2.0, 0.01);  // the cubes ring at speeds sqrt(2) apart: 0.13 %
  EXPECT_TRUE(std::filesystem::exists(dir / "out" / "report" / "report.md"));
}
