// A bilayer sheared along its interface: the lower layer sits on a clamp, a stick plate on the upper
// layer moves down and sideways, so the interface carries a growing normal force while the upper
// layer is dragged along it. Read from the contact force per material pair (history bookkeeping):
//   frictionless: the interface transmits no shear (net and summed tangential force < 0.5 % of the
//                 normal force), and the clamp under the lower layer feels no sideways force;
//   coulomb 0.3:  the transmitted shear never exceeds 0.3 x the normal force in any history row,
//                 and once the layers slide it reaches it (> 0.27 x), i.e. friction is transmitted.
// The upper layer is narrower than the lower one, so its corners rest on a flat surface.
#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <gtest/gtest.h>

#include "../deck_parts.hpp"
#include "../engine/scene_fixture.hpp"

using namespace pbx;

namespace {

std::string deck(const std::string& law) {
  return R"(
[run]
end_time = "4 us"
history_points = 41
snapshots = 0
[grid]
cell_size = "10 um"
min = ["-0.05 mm", "-0.06 mm"]
max = ["0.45 mm", "0.2 mm"]
)" + test::elastic("lower", 2.0, 1, 0.3) +
         test::elastic("upper", 2.0, 1, 0.3) + test::box_mm(0, 0, 0.4, 0.06, "lower") +
         test::box_mm(0.1, 0.06, 0.3, 0.12, "upper") +
         test::rigid_box_mm("clamp", 0, -0.04, 0.4, 0, 0, 1, "contact = \"stick\"\n") +
         test::rigid_box_mm("plate", 0.1, 0.12, 0.3, 0.16, 0, -1,
                            "contact = \"stick\"\nvelocity = [\"2 m/s\", \"-0.5 m/s\"]\nramp_time = \"0.5 us\"\n") +
         "[contact]\n" + law;
}

struct Row {
  double fn, ft, fx, fy;  // interface: normal, tangential, net force on "lower" from "upper", N/m
  double clamp_x, clamp_y;
};

std::vector<Row> shear(const std::string& law) {
  Scene<2> sc = test::scene_from(deck(law));
  Runner<2> runner(sc, test::quiet());
  EXPECT_EQ(runner.contact_pairs().size(), 1u);
  EXPECT_EQ(runner.contact_pairs().at(0).name, "lower_upper");
  const auto& cols = runner.columns();
  for (const char* c : {"contact_lower_upper_fn_N_per_m", "contact_lower_upper_ft_N_per_m",
                        "contact_lower_upper_fx_N_per_m", "contact_lower_upper_fy_N_per_m"})
    EXPECT_NE(std::find(cols.begin(), cols.end(), c), cols.end()) << c;
  std::vector<Row> rows;
  runner.run([&](const Measurement& m) {
    if (m.t == 0) return;
    const auto& f = m.pair_force.at(0);
    rows.push_back({f[0], f[1], f[2], f[3], m.body_force[0][0], m.body_force[0][1]});
  });
  return rows;
}

}  // namespace

TEST(BilayerShear, FrictionlessInterfaceTransmitsNoShear) {
  const auto rows = shear("default = \"frictionless\"\n");
  double fn_max = 0;
  for (const Row& r : rows) fn_max = std::max(fn_max, r.fn);
  ASSERT_GT(fn_max, 100.0);  // the plate really presses the layers together (N/m)
  for (const Row& r : rows) {
    if (r.fn < 0.1 * fn_max) continue;
    EXPECT_LT(std::abs(r.fx), 0.005 * r.fn);
    EXPECT_LT(r.ft, 0.005 * r.fn);
    EXPECT_NEAR(-r.fy, r.fn, 0.01 * r.fn);  // the upper layer pushes the lower one down
    EXPECT_LT(std::abs(r.clamp_x), 0.005 * std::abs(r.clamp_y));
    std::printf("frictionless: fn %.4g  ft/fn %.2e  fx/fn %.2e  clamp fx/fy %.2e\n", r.fn, r.ft / r.fn, r.fx / r.fn,
                r.clamp_x / r.clamp_y);
  }
}

TEST(BilayerShear, CoulombShearNeverExceedsMuTimesNormal) {
  const double mu = 0.3;
  const auto rows = shear(fmt::format("default = \"coulomb\"\nfriction = {}\n", mu));
  double ratio_max = 0, ratio_last = 0;
  for (const Row& r : rows) {
    if (r.fn <= 0) continue;
    EXPECT_LE(r.ft, mu * r.fn * (1 + 1e-9));
    EXPECT_LE(std::abs(r.fx), mu * r.fn * (1 + 1e-9));
    ratio_max = std::max(ratio_max, std::abs(r.fx) / r.fn);
    ratio_last = std::abs(r.fx) / r.fn;
    std::printf("coulomb: fn %.4g  ft/fn %.4f  fx/fn %.4f  clamp fx/fy %.4f\n", r.fn, r.ft / r.fn, r.fx / r.fn,
                r.clamp_x / r.clamp_y);
  }
  EXPECT_GT(ratio_last, 0.9 * mu);  // sliding at the end: the full Coulomb shear is transmitted
}
