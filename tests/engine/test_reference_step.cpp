// A reference step of each integrator written as the paper's algorithm (Section 2.1) in plain loops, kept as the
// oracle that the fast path must match (issue 26 item 3): P2G of mass, momentum and force with the
// kernels' 1-D weights (kernel_1d, not the solver's stencil code), the grid update, G2P by the
// FLIP/PIC blend, the position update with the PIC velocity, the velocity gradient, F, J and V,
// and the stress update by the scene's own material laws (tested on their own in tests/materials).
// The solver's USL step does all of this in its fused G2P -> stress -> next P2G pass, strip by
// strip, with its masks and threads, and its USF and MUSL steps in their separate stages; each must
// give the same particles as the plain algorithm to round-off.
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

#include "../deck_parts.hpp"
#include "scene_fixture.hpp"
#include "solver/kinematics.hpp"
#include "solver/material_batch.hpp"

using namespace pbx;

namespace {

std::string deck(const char* kernel, const std::string& integrator) {
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
integrator = "{}"
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
)",
                     kernel, integrator) +
         test::disk_mm(0.2, 0.2, 0.06, "tatb", "specimen") + test::disk_mm(0.2, 0.2, 0.1, "binder", "specimen");
}

// v = w x r + e r about the centre, identical in both scenes
void spin(Scene<2>& sc) {
  const Vec<2> c(0.2e-3, 0.2e-3);
  for (std::size_t p = 0; p < sc.particles.size(); ++p) {
    const Vec<2> r = sc.particles.x[p] - c;
    sc.particles.v[p] = 2e5 * Vec<2>(-r.y(), r.x()) + 1e5 * r;
  }
}

// One step of `integrator` on scene `sc` with step dt, written out (paper Section 2.1; USF and MUSL
// as docs/theory/engine.md states them):
//   USL:  P2G (m, p, f) -> grid update -> G2P (v, x, L from the updated velocities) -> stress
//   USF:  P2G (m, p) -> L from the interpolated velocities -> stress -> P2G (f) -> grid update -> G2P (v, x)
//   MUSL: P2G (m, p, f) -> grid update -> G2P (v) -> P2G of the new momenta -> L from them, x from the
//         updated grid velocities -> stress
template <Kernel K>
void reference_step(Scene<2>& sc, double dt, const std::string& integrator) {
  auto& P = sc.particles;
  const auto& g = sc.grid;
  const long nx = g.n[0], nn = g.nodes();
  const auto N = static_cast<std::size_t>(nn);
  const double inv_h = 1.0 / g.h, f = sc.settings.mass_scaling, alpha = sc.settings.flip;
  const double a = 0.5 / sc.settings.ppc;
  // each node of a particle's stencil with its weight and gradient
  auto each_node = [&](const Vec<2>& x, auto&& fn) {
    int base[2];
    std::array<double, 3> w[2], gr[2];
    for (int d = 0; d < 2; ++d) kernel_1d<K>((x[d] - g.origin[d]) * inv_h, a, inv_h, base[d], w[d], gr[d]);
    for (int j = 0; j < 3; ++j)
      for (int i = 0; i < 3; ++i)
        fn(static_cast<std::size_t>(base[0] + i + (base[1] + j) * nx), w[0][i] * w[1][j],
           Vec<2>(gr[0][i] * w[1][j], w[0][i] * gr[1][j]));
  };
  std::vector<double> m(N, 0.0);
  std::vector<Vec<2>> mom(N, Vec<2>::Zero()), force = mom, vel = mom, dvel = mom;
  auto p2g_mass_momentum = [&] {
    std::fill(m.begin(), m.end(), 0.0);
    std::fill(mom.begin(), mom.end(), Vec<2>::Zero());
    for (std::size_t p = 0; p < P.size(); ++p)
      each_node(P.x[p], [&](std::size_t i, double S, const Vec<2>&) {
        m[i] += S * f * P.mass[p];
        mom[i] += S * f * P.mass[p] * P.v[p];
      });
  };
  auto p2g_force = [&] {
    std::fill(force.begin(), force.end(), Vec<2>::Zero());
    for (std::size_t p = 0; p < P.size(); ++p) {
      Mat<2> sigma;
      sigma << P.stress[p].xx, P.stress[p].xy, P.stress[p].xy, P.stress[p].yy;
      each_node(P.x[p], [&](std::size_t i, double S, const Vec<2>& G) {
        force[i] += -P.volume[p] * (sigma * G) + S * P.mass[p] * sc.settings.gravity;
      });
    }
  };
  auto grid_update = [&] {
    for (std::size_t i = 0; i < N; ++i)
      if (m[i] > 0) {
        vel[i] = (mom[i] + dt * force[i]) / m[i];
        dvel[i] = dt * force[i] / m[i];
      }
  };
  // L from the nodal velocities v (grid order), then F, J, V and the material laws
  auto gradient = [&](const std::vector<Vec<2>>& v) {
    for (std::size_t p = 0; p < P.size(); ++p) {
      Mat<2> L = Mat<2>::Zero();
      each_node(P.x[p], [&](std::size_t i, double, const Vec<2>& G) { L += v[i] * G.transpose(); });
      P.L[p] = L;
    }
  };
  auto stress = [&] {
    for (std::size_t p = 0; p < P.size(); ++p) {
      P.F[p] = advance_deformation_gradient<2>(P.F[p], P.L[p], dt);
      P.volume[p] = P.F[p].determinant() * P.volume0[p];
    }
    for (std::size_t k = 0; k < sc.materials.size(); ++k) {
      auto& st = sc.material_state[k];
      sc.materials[k]->update(
          material_batch<2>(P, st, sc.materials[k]->history_size(), 0, static_cast<long>(st.index.size()), dt));
    }
  };
  // G2P: the FLIP/PIC velocity; the PIC velocity of every particle (its displacement over dt)
  auto g2p = [&] {
    std::vector<Vec<2>> vpic(P.size(), Vec<2>::Zero());
    for (std::size_t p = 0; p < P.size(); ++p) {
      Vec<2> dv = Vec<2>::Zero();
      each_node(P.x[p], [&](std::size_t i, double S, const Vec<2>&) {
        vpic[p] += S * vel[i];
        dv += S * dvel[i];
      });
      P.v[p] = alpha * (P.v[p] + dv) + (1 - alpha) * vpic[p];
    }
    return vpic;
  };
  auto move = [&](const std::vector<Vec<2>>& vpic) {
    for (std::size_t p = 0; p < P.size(); ++p) P.x[p] += dt * vpic[p];
  };
  if (integrator == "usl") {
    p2g_mass_momentum();
    p2g_force();
    grid_update();
    const auto vpic = g2p();
    gradient(vel);
    move(vpic);
    stress();
  } else if (integrator == "usf") {
    p2g_mass_momentum();
    std::vector<Vec<2>> v0(N, Vec<2>::Zero());
    for (std::size_t i = 0; i < N; ++i)
      if (m[i] > 0) v0[i] = mom[i] / m[i];
    gradient(v0);
    stress();
    p2g_force();
    grid_update();
    move(g2p());
  } else {  // musl
    p2g_mass_momentum();
    p2g_force();
    grid_update();
    const auto vpic = g2p();
    p2g_mass_momentum();  // the new momenta, at the start-of-step positions (the masses are unchanged)
    std::vector<Vec<2>> v1(N, Vec<2>::Zero());
    for (std::size_t i = 0; i < N; ++i)
      if (m[i] > 0) v1[i] = mom[i] / m[i];
    gradient(v1);
    move(vpic);
    stress();
  }
}

double sym_norm(const Sym3& s) { return std::sqrt(s.xx * s.xx + s.yy * s.yy + s.zz * s.zz + 2 * s.xy * s.xy); }

template <Kernel K>
void compare(const char* kernel, int threads, const std::string& integrator) {
  SCOPED_TRACE(fmt::format("{} {} on {} thread(s)", integrator, kernel, threads));
  omp_set_num_threads(threads);
  Scene<2> fast = test::scene_from(deck(kernel, integrator)), ref = test::scene_from(deck(kernel, integrator));
  spin(fast);
  spin(ref);
  Solver<2> solver(fast);
  double smax = 0, plastic = 0;
  for (int step = 0; step < 200; ++step) {
    solver.step();
    reference_step<K>(ref, solver.dt(), integrator);
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
      "%s %s, %d thread(s): max |dx| %.2e m, |dv| %.2e m/s (of %.3g), |dsigma| %.2e Pa (of %.3g); plastic %.3g\n",
      integrator.c_str(), kernel, threads, dx, dv, vmax, ds, smax, plastic);
  // the specimen really moves, strains and flows (else the comparison would test little)
  EXPECT_GT(smax, 1e7);
  EXPECT_GT(plastic, 1e-4);
  // round-off of sums taken in another order, over 60 steps
  EXPECT_LT(dx, 1e-12 * fast.grid.h);
  EXPECT_LT(dv, 1e-11 * vmax);  // measured 1e-14 relative after 60 steps
  EXPECT_LT(ds, 1e-10 * smax);
}

}  // namespace

TEST(ReferenceStep, FastStepOfEveryIntegratorMatchesThePlainAlgorithm) {
  const int threads = omp_get_max_threads();
  for (const std::string integrator : {"usl", "usf", "musl"})
    for (const int t : {1, 2}) {
      compare<Kernel::ugimp>("ugimp", t, integrator);
      compare<Kernel::bspline2>("bspline2", t, integrator);
      compare<Kernel::linear>("linear", t, integrator);
    }
  omp_set_num_threads(threads);
}
