// An elastic cylinder pressed onto a flat in plane strain (Hertz): the contact half-width is
//   a = sqrt(4 P R / (pi E*)),  1/E* = (1 - nu^2)/E + (1 - nu_f^2)/E_f,  P = force per unit length.
// By symmetry, a disk squeezed between two frictionless flats is its lower half pressed by a
// frictionless rigid plate on its diameter (the plate keeps the diameter straight and shear-free,
// and sigma_yy is compressive along it), so only the half-disk is modelled.
// The flat is a deformable field 100 times stiffer than the disk (E* within 1 % of the rigid-flat
// value, and included exactly), clamped two cells below its surface, meeting the disk through the
// field contact law (frictionless) with the displacement check at 0.8 cells. (Against a [[rigid]]
// flat the footprint is 40-90 % too wide at these resolutions: nodes at or behind a rigid face
// always take part, so the flat also stops the disk's nodes where its surface is still up to a
// cell away; the field law's displacement check removes that band.)
// a is measured from the contact pressure: the contact impulses the flat gives the disk's nodes in
// a step (mom - mom0 - dt force) sample Hertz's elliptic p0 sqrt(1 - x^2/a^2), whose second moment
// is a^2/4, so a = 2 sqrt(<x^2>). P is the normal contact force of the disk-flat pair (history
// bookkeeping). The staircase of the rasterised disk puts a flat of about sqrt(R h) under it, so
// Hertz is approached as a grows: on R = 32 cells every row with a >= 6.5 cells is within 10 %
// (final load, a/R = 0.25: +5.7 %), and the final error is smaller than on R = 16 cells (+12 %).
#include <cmath>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <gtest/gtest.h>

#include "../engine/scene_fixture.hpp"

using namespace pbx;

namespace {

constexpr double kR = 0.32e-3, kE = 1e9, kNu = 0.3, kEflat = 100e9;

std::string deck(double h) {
  return fmt::format(R"(
[run]
end_time = "5 us"
history_points = 26
snapshots = 0
[grid]
cell_size = {h}
min = [{gx0}, {gy0}]
max = [{gx1}, {gy1}]
[materials.disk]
model = "linear_elastic"
density = "1.0 g/cm3"
youngs_modulus = {E}
poisson_ratio = {nu}
[[geometry]]
shape = "disk"
center = [0, {R}]
radius = {R}
material = "disk"
[materials.flat]
model = "linear_elastic"
density = "100 g/cm3"
youngs_modulus = {Ef}
poisson_ratio = {nu}
[[geometry]]
min = [{fx0}, {fy0}]
max = [{fx1}, 0]
material = "flat"
[[rigid]]
name = "clamp"
min = [{fx0}, {cy0}]
max = [{fx1}, {cy1}]
normal = [0, 1]
contact = "stick"
[contact]
default = "frictionless"
position_check = {pc}
[[rigid]]
name = "plate"
min = [{fx0}, {R}]
max = [{fx1}, {py1}]
normal = [0, -1]
velocity = [0, "-5 m/s"]
ramp_time = "1.2 us"
)",
                     fmt::arg("h", h), fmt::arg("R", kR), fmt::arg("E", kE), fmt::arg("nu", kNu),
                     fmt::arg("gx0", -kR - 6 * h), fmt::arg("gx1", kR + 6 * h), fmt::arg("gy0", -8 * h),
                     fmt::arg("gy1", 2 * kR + 3 * h), fmt::arg("fx0", -kR - 3 * h), fmt::arg("fx1", kR + 3 * h),
                     fmt::arg("fy0", -4 * h), fmt::arg("cy0", -6 * h), fmt::arg("cy1", -2 * h), fmt::arg("Ef", kEflat),
                     fmt::arg("pc", 0.8), fmt::arg("py1", kR + 2 * h));
}

struct Contact {
  double P, a, a_hertz, row_force;
};

std::vector<Contact> press(double h) {
  Scene<2> sc = test::scene_from(deck(h));
  test::keep_particles(sc, [](const Vec<2>& x) { return x.y() < kR; });  // the lower half-disk
  Runner<2> runner(sc, test::quiet());
  const double Estar = 1.0 / ((1 - kNu * kNu) / kE + (1 - kNu * kNu) / kEflat);
  std::vector<Contact> out;
  runner.run([&](const Measurement& m) {
    const double P = m.pair_force.at(0)[0];  // flat's push on the disk (normal contact force)
    if (!(P > 0)) return;
    // contact force per node of the flat in the last step: what the contact passes added to the
    // disk field's momentum, mom - mom0 - dt force (USL), at the nodes in the lower half
    const Grid<2>& g = sc.grid;
    const double dt = runner.solver().dt();
    double w = 0, wx = 0, wxx = 0;
    for (long i = 0; i < g.nodes(); ++i) {
      const Vec<2> x = g.position(i);
      if (x.y() > 0.5 * kR || !(g.mass[i] > 0)) continue;  // field 0 is the disk
      const double q = (g.mom[i] - g.mom0[i] - dt * g.force[i]).y() / dt;
      w += q;
      wx += q * x.x();
      wxx += q * x.x() * x.x();
    }
    const double mean = wx / w;
    out.push_back({P, 2 * std::sqrt(wxx / w - mean * mean), std::sqrt(4 * P * kR / (M_PI * Estar)), w});
  });
  return out;
}

// Relative error of the half-width at the last row; with `strict`, rows where a spans 6.5 cells or
// more must be within 10 %.
double final_error(double h, bool strict) {
  double last = 1.0;
  for (const Contact& c : press(h)) {
    const std::string at = fmt::format("h = {} um, P = {:.4g} N/m", h * 1e6, c.P);
    std::printf("%s: a = %.4g um, Hertz %.4g um (%+.1f %%), a/h = %.2f, nodal force / P = %.3f\n", at.c_str(),
                c.a * 1e6, c.a_hertz * 1e6, 100 * (c.a / c.a_hertz - 1), c.a_hertz / h, c.row_force / c.P);
    if (strict && c.a_hertz >= 6.5 * h) {
      EXPECT_NEAR(c.a, c.a_hertz, 0.10 * c.a_hertz) << at;
    }
    last = c.a / c.a_hertz - 1;
  }
  return last;
}

}  // namespace

// The half-width converges at first order in the cell (grid contact acts on a band of nodes about a
// cell wide): measured +11.2 % at R = 16 cells and +5.2 % at R = 32 (ratio 2.15, order 1.1). The
// first-order Richardson value 2 a(h/2) - a(h) removes that band and must give Hertz within 3 %
// (measured -0.8 %): a wrong plane-strain modulus (a factor 1/(1 - nu^2) = 1.10 on E*, 4.6 % on a)
// or a 10 % error in a material's modulus (5 % on a) fails it, where the 10 % band on a at one cell
// size (about 20 % on P/E*) let both through.
TEST(Hertz, ContactHalfWidthOfACylinderOnAStiffFlat) {
  const double coarse = final_error(20e-6, false), fine = final_error(10e-6, true);
  const double richardson = 2 * fine - coarse, order = std::log2(coarse / fine);
  std::printf(
      "Hertz half-width at the final load: %+.1f %% (R = 16 cells), %+.1f %% (R = 32 cells); first-order "
      "Richardson %+.2f %%, observed order %.2f\n",
      100 * coarse, 100 * fine, 100 * richardson, order);
  EXPECT_LT(std::abs(fine), 0.10);
  EXPECT_GT(order, 0.7);  // first order (a band of nodes a cell wide)
  EXPECT_LT(order, 1.5);
  EXPECT_LT(std::abs(richardson), 0.03);
}
