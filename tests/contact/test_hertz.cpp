#include "setup/build_scene.hpp"
// An elastic cylinder pressed onto a flat in plane strain (Hertz): the contact half-width is
#include "setup/build_scene.hpp"
//   a = sqrt(4 P R / (pi E*)),  1/E* = (1 - nu^2)/E + (1 - nu_f^2)/E_f,  P = force per unit length.
#include "setup/build_scene.hpp"
// By symmetry, a disk squeezed between two frictionless flats is its lower half pressed by a
#include "setup/build_scene.hpp"
// frictionless rigid plate on its diameter (the plate keeps the diameter straight and shear-free,
#include "setup/build_scene.hpp"
// and sigma_yy is compressive along it), so only the half-disk is modelled.
#include "setup/build_scene.hpp"
// The flat is a deformable field 100 times stiffer than the disk (E* within 1 % of the rigid-flat
#include "setup/build_scene.hpp"
// value, and included exactly), clamped two cells below its surface, meeting the disk through the
#include "setup/build_scene.hpp"
// field contact law (frictionless) with the displacement check at 0.8 cells. (Against a [[rigid]]
#include "setup/build_scene.hpp"
// flat the footprint is 40-90 % too wide at these resolutions: nodes at or behind a rigid face
#include "setup/build_scene.hpp"
// always take part, so the flat also stops the disk's nodes where its surface is still up to a
#include "setup/build_scene.hpp"
// cell away; the field law's displacement check removes that band.)
#include "setup/build_scene.hpp"
// a is measured from the contact pressure: the contact impulses the flat gives the disk's nodes in
#include "setup/build_scene.hpp"
// a step (mom - mom0 - dt force) sample Hertz's elliptic p0 sqrt(1 - x^2/a^2), whose second moment
#include "setup/build_scene.hpp"
// is a^2/4, so a = 2 sqrt(<x^2>). P is the normal contact force of the disk-flat pair (history
#include "setup/build_scene.hpp"
// bookkeeping). The staircase of the rasterised disk puts a flat of about sqrt(R h) under it, so
#include "setup/build_scene.hpp"
// Hertz is approached as a grows: on R = 32 cells every row with a >= 6.5 cells is within 10 %
#include "setup/build_scene.hpp"
// (final load, a/R = 0.25: +5.7 %), and the final error is smaller than on R = 16 cells (+12 %).
#include "setup/build_scene.hpp"
#include <cmath>
#include "setup/build_scene.hpp"
#include <string>
#include "setup/build_scene.hpp"
#include <vector>
#include "setup/build_scene.hpp"

#include "setup/build_scene.hpp"
#include <fmt/format.h>
#include "setup/build_scene.hpp"
#include <gtest/gtest.h>
#include "setup/build_scene.hpp"

#include "setup/build_scene.hpp"
#include "../engine/scene_fixture.hpp"
#include "setup/build_scene.hpp"

#include "setup/build_scene.hpp"
using namespace pbx;
#include "setup/build_scene.hpp"

#include "setup/build_scene.hpp"
namespace {
#include "setup/build_scene.hpp"

#include "setup/build_scene.hpp"
constexpr double kR = 0.32e-3, kE = 1e9, kNu = 0.3, kEflat = 100e9;
#include "setup/build_scene.hpp"

#include "setup/build_scene.hpp"
std::string deck(double h) {
#include "setup/build_scene.hpp"
  return fmt::format(R"(
#include "setup/build_scene.hpp"
[run]
#include "setup/build_scene.hpp"
end_time = "5 us"
#include "setup/build_scene.hpp"
history_points = 26
#include "setup/build_scene.hpp"
snapshots = 0
#include "setup/build_scene.hpp"
[grid]
#include "setup/build_scene.hpp"
cell_size = {h}
#include "setup/build_scene.hpp"
min = [{gx0}, {gy0}]
#include "setup/build_scene.hpp"
max = [{gx1}, {gy1}]
#include "setup/build_scene.hpp"
[materials.disk]
#include "setup/build_scene.hpp"
model = "linear_elastic"
#include "setup/build_scene.hpp"
density = "1.0 g/cm3"
#include "setup/build_scene.hpp"
youngs_modulus = {E}
#include "setup/build_scene.hpp"
poisson_ratio = {nu}
#include "setup/build_scene.hpp"
[[geometry]]
#include "setup/build_scene.hpp"
shape = "disk"
#include "setup/build_scene.hpp"
center = [0, {R}]
#include "setup/build_scene.hpp"
radius = {R}
#include "setup/build_scene.hpp"
material = "disk"
#include "setup/build_scene.hpp"
[materials.flat]
#include "setup/build_scene.hpp"
model = "linear_elastic"
#include "setup/build_scene.hpp"
density = "100 g/cm3"
#include "setup/build_scene.hpp"
youngs_modulus = {Ef}
#include "setup/build_scene.hpp"
poisson_ratio = {nu}
#include "setup/build_scene.hpp"
[[geometry]]
#include "setup/build_scene.hpp"
min = [{fx0}, {fy0}]
#include "setup/build_scene.hpp"
max = [{fx1}, 0]
#include "setup/build_scene.hpp"
material = "flat"
#include "setup/build_scene.hpp"
[[rigid]]
#include "setup/build_scene.hpp"
name = "clamp"
#include "setup/build_scene.hpp"
min = [{fx0}, {cy0}]
#include "setup/build_scene.hpp"
max = [{fx1}, {cy1}]
#include "setup/build_scene.hpp"
normal = [0, 1]
#include "setup/build_scene.hpp"
contact = "stick"
#include "setup/build_scene.hpp"
[contact]
#include "setup/build_scene.hpp"
default = "frictionless"
#include "setup/build_scene.hpp"
position_check = {pc}
#include "setup/build_scene.hpp"
[[rigid]]
#include "setup/build_scene.hpp"
name = "plate"
#include "setup/build_scene.hpp"
min = [{fx0}, {R}]
#include "setup/build_scene.hpp"
max = [{fx1}, {py1}]
#include "setup/build_scene.hpp"
normal = [0, -1]
#include "setup/build_scene.hpp"
velocity = [0, "-5 m/s"]
#include "setup/build_scene.hpp"
ramp_time = "1.2 us"
#include "setup/build_scene.hpp"
)",
#include "setup/build_scene.hpp"
                     fmt::arg("h", h), fmt::arg("R", kR), fmt::arg("E", kE), fmt::arg("nu", kNu),
#include "setup/build_scene.hpp"
                     fmt::arg("gx0", -kR - 6 * h), fmt::arg("gx1", kR + 6 * h), fmt::arg("gy0", -8 * h),
#include "setup/build_scene.hpp"
                     fmt::arg("gy1", 2 * kR + 3 * h), fmt::arg("fx0", -kR - 3 * h), fmt::arg("fx1", kR + 3 * h),
#include "setup/build_scene.hpp"
                     fmt::arg("fy0", -4 * h), fmt::arg("cy0", -6 * h), fmt::arg("cy1", -2 * h), fmt::arg("Ef", kEflat),
#include "setup/build_scene.hpp"
                     fmt::arg("pc", 0.8), fmt::arg("py1", kR + 2 * h));
#include "setup/build_scene.hpp"
}
#include "setup/build_scene.hpp"

#include "setup/build_scene.hpp"
// Keeps the particles below the diameter (y < R): rebuilds the particle arrays and the material
#include "setup/build_scene.hpp"
// batches the way build_scene does.
#include "setup/build_scene.hpp"
void keep_lower_half(Scene<2>& sc) {
#include "setup/build_scene.hpp"
  Particles<2> kept;
#include "setup/build_scene.hpp"
  const auto& P = sc.particles;
#include "setup/build_scene.hpp"
  for (std::size_t p = 0; p < P.size(); ++p)
#include "setup/build_scene.hpp"
    if (P.x[p].y() < kR) kept.add(P.x[p], P.volume0[p], P.mass[p], P.material[p], P.field[p]);
#include "setup/build_scene.hpp"
  sc.particles = std::move(kept);
#include "setup/build_scene.hpp"
  for (std::size_t m = 0; m < sc.materials.size(); ++m) {
#include "setup/build_scene.hpp"
    auto& st = sc.material_state[m];
#include "setup/build_scene.hpp"
    st.index.clear();
#include "setup/build_scene.hpp"
    for (std::size_t p = 0; p < sc.particles.size(); ++p)
#include "setup/build_scene.hpp"
      if (sc.particles.material[p] == static_cast<int>(m)) {
#include "setup/build_scene.hpp"
        sc.particles.slot[p] = static_cast<std::uint32_t>(st.index.size());
#include "setup/build_scene.hpp"
        st.index.push_back(static_cast<std::uint32_t>(p));
#include "setup/build_scene.hpp"
      }
#include "setup/build_scene.hpp"
    const int hs = sc.materials[m]->history_size();
#include "setup/build_scene.hpp"
    st.history.assign(st.index.size() * static_cast<std::size_t>(hs), 0.0);
#include "setup/build_scene.hpp"
    for (std::size_t k = 0; k < st.index.size(); ++k) sc.materials[m]->init_history(st.history.data() + k * hs);
#include "setup/build_scene.hpp"
  }
#include "setup/build_scene.hpp"
}
#include "setup/build_scene.hpp"

#include "setup/build_scene.hpp"
struct Contact {
#include "setup/build_scene.hpp"
  double P, a, a_hertz, row_force;
#include "setup/build_scene.hpp"
};
#include "setup/build_scene.hpp"

#include "setup/build_scene.hpp"
std::vector<Contact> press(double h) {
#include "setup/build_scene.hpp"
  Scene<2> sc = test::scene_from(deck(h));
#include "setup/build_scene.hpp"
  keep_lower_half(sc);
#include "setup/build_scene.hpp"
  Runner<2> runner(sc, test::quiet());
#include "setup/build_scene.hpp"
  const double Estar = 1.0 / ((1 - kNu * kNu) / kE + (1 - kNu * kNu) / kEflat);
#include "setup/build_scene.hpp"
  std::vector<Contact> out;
#include "setup/build_scene.hpp"
  runner.run([&](const Measurement& m) {
#include "setup/build_scene.hpp"
    const double P = m.pair_force.at(0)[0];  // flat's push on the disk (normal contact force)
#include "setup/build_scene.hpp"
    if (!(P > 0)) return;
#include "setup/build_scene.hpp"
      // contact force per node of the flat in the last step: what the contact passes added to the
#include "setup/build_scene.hpp"
      // disk field's momentum, mom - mom0 - dt force (USL), at the nodes in the lower half
#include "setup/build_scene.hpp"
    const Grid<2>& g = sc.grid;
#include "setup/build_scene.hpp"
    const double dt = runner.solver().dt();
#include "setup/build_scene.hpp"
    double w = 0, wx = 0, wxx = 0;
#include "setup/build_scene.hpp"
    for (long i = 0; i < g.nodes(); ++i) {
#include "setup/build_scene.hpp"
      const Vec<2> x = g.position(i);
#include "setup/build_scene.hpp"
      if (x.y() > 0.5 * kR || !(g.mass[i] > 0)) continue;  // field 0 is the disk
#include "setup/build_scene.hpp"
      const double q = (g.mom[i] - g.mom0[i] - dt * g.force[i]).y() / dt;
#include "setup/build_scene.hpp"
      w += q;
#include "setup/build_scene.hpp"
      wx += q * x.x();
#include "setup/build_scene.hpp"
      wxx += q * x.x() * x.x();
#include "setup/build_scene.hpp"
    }
#include "setup/build_scene.hpp"
    const double mean = wx / w;
#include "setup/build_scene.hpp"
    out.push_back({P, 2 * std::sqrt(wxx / w - mean * mean), std::sqrt(4 * P * kR / (M_PI * Estar)), w});
#include "setup/build_scene.hpp"
  });
#include "setup/build_scene.hpp"
  return out;
#include "setup/build_scene.hpp"
}
#include "setup/build_scene.hpp"

#include "setup/build_scene.hpp"
// Relative error of the half-width at the last row; with `strict`, rows where a spans 6.5 cells or
#include "setup/build_scene.hpp"
// more must be within 10 %.
#include "setup/build_scene.hpp"
double final_error(double h, bool strict) {
#include "setup/build_scene.hpp"
  double last = 1.0;
#include "setup/build_scene.hpp"
  for (const Contact& c : press(h)) {
#include "setup/build_scene.hpp"
    const std::string at = fmt::format("h = {} um, P = {:.4g} N/m", h * 1e6, c.P);
#include "setup/build_scene.hpp"
    std::printf("%s: a = %.4g um, Hertz %.4g um (%+.1f %%), a/h = %.2f, nodal force / P = %.3f\n", at.c_str(),
#include "setup/build_scene.hpp"
                c.a * 1e6, c.a_hertz * 1e6, 100 * (c.a / c.a_hertz - 1), c.a_hertz / h, c.row_force / c.P);
#include "setup/build_scene.hpp"
    if (strict && c.a_hertz >= 6.5 * h) {
#include "setup/build_scene.hpp"
      EXPECT_NEAR(c.a, c.a_hertz, 0.10 * c.a_hertz) << at;
#include "setup/build_scene.hpp"
    }
#include "setup/build_scene.hpp"
    last = c.a / c.a_hertz - 1;
#include "setup/build_scene.hpp"
  }
#include "setup/build_scene.hpp"
  return last;
#include "setup/build_scene.hpp"
}
#include "setup/build_scene.hpp"

#include "setup/build_scene.hpp"
}  // namespace
#include "setup/build_scene.hpp"

#include "setup/build_scene.hpp"
// The half-width converges at first order in the cell (grid contact acts on a band of nodes about a
#include "setup/build_scene.hpp"
// cell wide): measured +11.2 % at R = 16 cells and +5.2 % at R = 32 (ratio 2.15, order 1.1). The
#include "setup/build_scene.hpp"
// first-order Richardson value 2 a(h/2) - a(h) removes that band and must give Hertz within 3 %
#include "setup/build_scene.hpp"
// (measured -0.8 %): a wrong plane-strain modulus (a factor 1/(1 - nu^2) = 1.10 on E*, 4.6 % on a)
#include "setup/build_scene.hpp"
// or a 10 % error in a material's modulus (5 % on a) fails it, where the 10 % band on a at one cell
#include "setup/build_scene.hpp"
// size (about 20 % on P/E*) let both through.
#include "setup/build_scene.hpp"
TEST(Hertz, ContactHalfWidthOfACylinderOnAStiffFlat) {
#include "setup/build_scene.hpp"
  const double coarse = final_error(20e-6, false), fine = final_error(10e-6, true);
#include "setup/build_scene.hpp"
  const double richardson = 2 * fine - coarse, order = std::log2(coarse / fine);
#include "setup/build_scene.hpp"
  std::printf(
#include "setup/build_scene.hpp"
      "Hertz half-width at the final load: %+.1f %% (R = 16 cells), %+.1f %% (R = 32 cells); first-order "
#include "setup/build_scene.hpp"
      "Richardson %+.2f %%, observed order %.2f\n",
#include "setup/build_scene.hpp"
      100 * coarse, 100 * fine, 100 * richardson, order);
#include "setup/build_scene.hpp"
  EXPECT_LT(std::abs(fine), 0.10);
#include "setup/build_scene.hpp"
  EXPECT_GT(order, 0.7);  // first order (a band of nodes a cell wide)
#include "setup/build_scene.hpp"
  EXPECT_LT(order, 1.5);
#include "setup/build_scene.hpp"
  EXPECT_LT(std::abs(richardson), 0.03);
#include "setup/build_scene.hpp"
}
