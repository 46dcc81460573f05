// A reference USL step written as the paper's algorithm (Section 2.1) in plain loops, kept as the
// oracle that the fast path must match (issue 26 item 3): P2G of mass, momentum and force with the
// kernels' 1-D weights (kernel_1d, not the solver's stencil code), the grid update, G2P by the
// FLIP/PIC blend, the position update with the PIC velocity, the velocity gradient, F, J and V,
// and the stress update by the scene's own material laws (tested on their own in tests/materials).
// The solver's USL step does all of this in its fused G2P -> stress -> next P2G pass, strip by
// strip, with its masks and threads; the two must give the same particles to round-off.
//
// The specimen: a plastic TATB disk (J2 + Mie-Grueneisen, yield lowered so it flows) inside a
// viscoelastic binder ring (Prony + Tait: history variables), one velocity field, gravity, mass
// scaling 4, spinning and expanding (v = w x r + e r) so the stresses and the plastic flow are
// nonzero and particles cross cells. Each shape function, 1 and 2 threads, 200 steps. Both materials
// on one velocity field: with one field per material the weld of the two fields changes each
// field's FLIP increment at the shared nodes, which a single-field reference does not have.
#include <algorithm>
#include <cmath>
#include <vector>

#include <fmt/format.h>
#include <omp.h>

#include <gtest/gtest.h>

#include "scene_fixture.hpp"
#include "solver/kinematics.hpp"
#include "solver/material_batch.hpp"

using namespace pbx;

namespace {

std::string deck(const char* kernel) {
  return fmt::format(R"(
[run]
end_time = "1 ms"
history_points = 2
snapshots = 0
[grid]
cell_size = "10 um"
shape_function = "{}"
min = ["0 mm", "0 mm"]
max = ["0.4 mm", "0.4 mm"]
[solver]
mass_scaling = 4
flip = 0.9
cfl = 0.3
gravity = ["3e5 m/s2", "-2e5 m/s2"]
[materials.tatb]
model = "j2_mie_gruneisen"
density = "1.934 g/cm3"
shear_modulus = "11.5 GPa"
yield_stress = "20 MPa"
hardening_modulus = "1 GPa"
sound_speed = "2340 m/s"
hugoniot_s1 = 2.32
gruneisen_gamma0 = 1.60
[materials.binder]
model = "viscoelastic_tait"
density = "2.02 g/cm3"
long_term_shear_modulus = "10 MPa"
prony_shear_moduli = ["50 MPa", "20 MPa"]
prony_shear_times = ["1e-7 s", "1e-6 s"]
tait_c = 0.08936
tait_k0 = "0.27 GPa"
[[geometry]]
shape = "disk"
center = ["0.2 mm", "0.2 mm"]
radius = "0.06 mm"
material = "tatb"
field = "specimen"
[[geometry]]
shape = "disk"
center = ["0.2 mm", "0.2 mm"]
radius = "0.1 mm"
material = "binder"
field = "specimen"
)",
                     kernel);
}

// v = w x r + e r about the centre, identical in both scenes
void spin(Scene<2>& sc) {
  const Vec<2> c(0.2e-3, 0.2e-3);
  for (std::size_t p = 0; p < sc.particles.size(); ++p) {
    const Vec<2> r = sc.particles.x[p] - c;
    sc.particles.v[p] = 2e5 * Vec<2>(-r.y(), r.x()) + 1e5 * r;
  }
}

// One USL step on scene `sc` with step dt, written out.
template <Kernel K>
void reference_step(Scene<2>& sc, double dt) {
  auto& P = sc.particles;
  const auto& g = sc.grid;
  const long nx = g.n[0], nn = g.nodes();
  const double inv_h = 1.0 / g.h, f = sc.settings.mass_scaling, alpha = sc.settings.flip;
  const double a = 0.5 / sc.settings.ppc;
  struct W {
    int base[2];
    std::array<double, 3> w[2], gr[2];
  };
  auto weights = [&](const Vec<2>& x) {
    W s;
    for (int d = 0; d < 2; ++d) kernel_1d<K>((x[d] - g.origin[d]) * inv_h, a, inv_h, s.base[d], s.w[d], s.gr[d]);
    return s;
  };
  // P2G
  std::vector<double> m(static_cast<std::size_t>(nn), 0.0);
  std::vector<Vec<2>> mom(static_cast<std::size_t>(nn), Vec<2>::Zero()), force = mom;
  for (std::size_t p = 0; p < P.size(); ++p) {
    const W s = weights(P.x[p]);
    Mat<2> sigma;
    sigma << P.stress[p].xx, P.stress[p].xy, P.stress[p].xy, P.stress[p].yy;
    for (int j = 0; j < 3; ++j)
      for (int i = 0; i < 3; ++i) {
        const auto node = static_cast<std::size_t>(s.base[0] + i + (s.base[1] + j) * nx);
        const double S = s.w[0][i] * s.w[1][j];
        const Vec<2> G(s.gr[0][i] * s.w[1][j], s.w[0][i] * s.gr[1][j]);
        m[node] += S * f * P.mass[p];
        mom[node] += S * f * P.mass[p] * P.v[p];
        force[node] += -P.volume[p] * (sigma * G) + S * P.mass[p] * sc.settings.gravity;
      }
  }
  // grid update
  std::vector<Vec<2>> vel(static_cast<std::size_t>(nn), Vec<2>::Zero()), dvel = vel;
  for (std::size_t i = 0; i < static_cast<std::size_t>(nn); ++i)
    if (m[i] > 0) {
      vel[i] = (mom[i] + dt * force[i]) / m[i];
      dvel[i] = dt * force[i] / m[i];
    }
  // G2P, kinematics
  for (std::size_t p = 0; p < P.size(); ++p) {
    const W s = weights(P.x[p]);
    Vec<2> vpic = Vec<2>::Zero(), dv = Vec<2>::Zero();
    Mat<2> L = Mat<2>::Zero();
    for (int j = 0; j < 3; ++j)
      for (int i = 0; i < 3; ++i) {
        const auto node = static_cast<std::size_t>(s.base[0] + i + (s.base[1] + j) * nx);
        const double S = s.w[0][i] * s.w[1][j];
        const Vec<2> G(s.gr[0][i] * s.w[1][j], s.w[0][i] * s.gr[1][j]);
        vpic += S * vel[node];
        dv += S * dvel[node];
        L += vel[node] * G.transpose();
      }
    P.v[p] = alpha * (P.v[p] + dv) + (1 - alpha) * vpic;
    P.x[p] += dt * vpic;
    P.L[p] = L;
    P.F[p] = advance_deformation_gradient<2>(P.F[p], L, dt);
    P.volume[p] = P.F[p].determinant() * P.volume0[p];
  }
  // stress update, one batch per material
  for (std::size_t k = 0; k < sc.materials.size(); ++k) {
    auto& st = sc.material_state[k];
    const MaterialBatch<2> b =
        material_batch<2>(P, st, sc.materials[k]->history_size(), 0, static_cast<long>(st.index.size()), dt);
    sc.materials[k]->update(b);
  }
}

double sym_norm(const Sym3& s) { return std::sqrt(s.xx * s.xx + s.yy * s.yy + s.zz * s.zz + 2 * s.xy * s.xy); }

template <Kernel K>
void compare(const char* kernel, int threads) {
  SCOPED_TRACE(fmt::format("{} on {} thread(s)", kernel, threads));
  omp_set_num_threads(threads);
  Scene<2> fast = test::scene_from(deck(kernel)), ref = test::scene_from(deck(kernel));
  spin(fast);
  spin(ref);
  Solver<2> solver(fast);
  double smax = 0, plastic = 0;
  for (int step = 0; step < 200; ++step) {
    solver.step();
    reference_step<K>(ref, solver.dt());
  }
  const auto& A = fast.particles;
  const auto& B = ref.particles;
  ASSERT_EQ(A.size(), B.size());
  double dx = 0, dv = 0, ds = 0, vmax = 0;
  for (std::size_t p = 0; p < A.size(); ++p) {
    dx = std::max(dx, (A.x[p] - B.x[p]).norm());
    dv = std::max(dv, (A.v[p] - B.v[p]).norm());
    const Sym3& a = A.stress[p];
    const Sym3& b = B.stress[p];
    ds = std::max(ds, sym_norm(Sym3{a.xx - b.xx, a.yy - b.yy, a.zz - b.zz, a.xy - b.xy, a.yz - b.yz, a.zx - b.zx}));
    smax = std::max(smax, sym_norm(a));
    vmax = std::max(vmax, A.v[p].norm());
  }
  for (std::size_t m = 0; m < fast.materials.size(); ++m) {
    const auto& st = fast.material_state[m];
    const int hs = fast.materials[m]->history_size();
    for (std::size_t k = 0; k < st.index.size(); ++k)
      plastic = std::max(plastic, fast.materials[m]->plastic_strain(st.history.data() + k * hs));
  }
  std::printf(
      "%s, %d thread(s): max |dx| %.2e m, |dv| %.2e m/s (of %.3g), |dsigma| %.2e Pa (of %.3g); plastic strain %.3g\n",
      kernel, threads, dx, dv, vmax, ds, smax, plastic);
  // the specimen really moves, strains and flows (else the comparison would test little)
  EXPECT_GT(smax, 1e7);
  EXPECT_GT(plastic, 1e-4);
  // round-off of sums taken in another order, over 60 steps
  EXPECT_LT(dx, 1e-12 * fast.grid.h);
  EXPECT_LT(dv, 1e-11 * vmax);  // measured 1e-14 relative after 60 steps
  EXPECT_LT(ds, 1e-10 * smax);
}

}  // namespace

TEST(ReferenceStep, FastUslStepMatchesThePlainAlgorithm) {
  const int threads = omp_get_max_threads();
  for (const int t : {1, 2}) {
    compare<Kernel::ugimp>("ugimp", t);
    compare<Kernel::bspline2>("bspline2", t);
    compare<Kernel::linear>("linear", t);
  }
  omp_set_num_threads(threads);
}
