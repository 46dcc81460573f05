#include "solver/solver.hpp"

#include <cmath>
#include <limits>

#include <fmt/format.h>

#include "contact/field_contact.hpp"
#include "contact/rigid_contact.hpp"
#include "core/error.hpp"
#include "core/parallel.hpp"

namespace pbx {

namespace {

// In-plane (D x D) block of a stored 3x3 Cauchy stress.
template <int D>
inline Mat<D> in_plane(const Sym3& s) {
  if constexpr (D == 2) {
    Mat<2> m;
    m << s.xx, s.xy, s.xy, s.yy;
    return m;
  } else {
    return s.mat();
  }
}

// Calls f with the run's kernel as a compile-time constant: one switch per stage, not per particle.
template <class F>
void with_kernel(Kernel k, F&& f) {
  switch (k) {
    case Kernel::linear: f(std::integral_constant<Kernel, Kernel::linear>{}); break;
    case Kernel::ugimp: f(std::integral_constant<Kernel, Kernel::ugimp>{}); break;
    case Kernel::bspline2: f(std::integral_constant<Kernel, Kernel::bspline2>{}); break;
  }
}

constexpr std::uint32_t kNone = std::numeric_limits<std::uint32_t>::max();

// A strip's members are runs of a few consecutive particles (one row of cells across the strip),
// so the hardware prefetchers miss the jump from one run to the next: the scatter and gather
// loops ask for the data of the particle kPrefetchAhead members ahead.
constexpr std::size_t kPrefetchAhead = 8;
template <class... T>
inline void prefetch(const T*... p) {
  (__builtin_prefetch(p), ...);
}

// The end-of-step check of a particle just moved to x, made where its position is updated (no
// separate pass over the particles): every particle must keep its whole stencil inside the grid
// (`left` collects the lowest offending index), and a particle that crossed out of its strip
// needs a re-bin (`rebin`; rare: strains are small).
template <int D>
inline void check_position(const Grid<D>& g, const StripBins& bins, double inv_h, std::uint32_t p, const Vec<D>& x,
                           long strip, std::uint32_t& left, bool& rebin) {
  for (int d = 0; d < D; ++d) {
    const double s = (x[d] - g.origin[d]) * inv_h;
    if (!(s >= 1.0 && s < static_cast<double>(g.n[d]) - 2.0)) left = std::min(left, p);
    else if (d == 0 && bins.strip_of(s) != strip) rebin = true;
  }
}

}  // namespace

template <int D>
Solver<D>::Solver(Scene<D>& scene) : sc_(scene) {
  const auto& P = sc_.particles;
  bins_.setup(sc_.grid.n[0] - 1);
  rebuild_bins();
  double msum = 0;
  for (double m : P.mass) msum += m;
  mass_eps_ = 1e-20 * sc_.settings.mass_scaling * msum / static_cast<double>(std::max<std::size_t>(1, P.size()));
  half_width_ = 0.5 / sc_.settings.ppc;
  for (auto& m : sc_.materials) cmax_ = std::max(cmax_, m->initial_wave_speed());
  for (auto& v : P.v) vmax_ = std::max(vmax_, v.norm());
  track_gradients_ = sc_.deformable_fields > 1;
  contact_tally_ = ContactTally<D>(sc_.deformable_fields);
  static_presence_.resize(sc_.bodies.size());
}

template <int D>
void Solver<D>::restore(const State& s) {
  t_ = s.t;
  dt_ = s.dt;
  cmax_ = s.cmax;
  vmax_ = s.vmax;
  internal_ = s.internal;
  dissipated_ = s.dissipated;
  steps_ = s.steps;
  for (auto& b : sc_.bodies) b.move_to(t_);
  left_grid_ = kNone;
  rebin_ = false;
  rebuild_bins();
}

template <int D>
void Solver<D>::rebuild_bins() {
  const auto& P = sc_.particles;
  const double inv_h = 1.0 / sc_.grid.h;
  for (auto& m : bins_.members) m.clear();
  for (std::size_t p = 0; p < P.size(); ++p) {
    bins_.members[static_cast<std::size_t>(bins_.strip_of((P.x[p][0] - sc_.grid.origin[0]) * inv_h))].push_back(static_cast<std::uint32_t>(p));
  }
}

template <int D>
double Solver<D>::stable_time_step() const {
  const double c = cmax_ / std::sqrt(sc_.settings.mass_scaling) + vmax_;
  return sc_.settings.cfl * sc_.grid.h / c;
}

// ------------------------------------------------------------------------------------- the step
template <int D>
void Solver<D>::step() {
  dt_ = stable_time_step();
  reset_grid();
  rigid_p2g();
  switch (sc_.settings.integrator) {
    case Integrator::usf:
      p2g(false);
      contact(true);
      velocity_gradient();
      update_stress();
      p2g_forces();
      grid_update();
      contact(true);
      finalize_grid_velocities();
      g2p();
      break;
    case Integrator::usl:
      p2g(true);
      contact(true);
      grid_update();
      contact(true);
      finalize_grid_velocities();
      g2p();  // also takes L from the updated nodal velocities
      update_stress();
      break;
    case Integrator::musl:
      p2g(true);
      contact(true);
      grid_update();
      contact(true);
      finalize_grid_velocities();
      g2p();  // also maps the updated particle momenta back to the grid
      contact(false);
      remap_velocity_gradient();
      update_stress();
      break;
  }
  t_ += dt_;
  ++steps_;
  advance_bodies();
}

// ------------------------------------------------------------------------------------- stages
template <int D>
void Solver<D>::reset_grid() {
  auto& g = sc_.grid;
  // in parallel: a serial reset is the largest serial part of a step on two threads
  const long n = static_cast<long>(g.mass.size()), nr = static_cast<long>(g.presence.size());
  const bool gradients = track_gradients_;
#pragma omp parallel
  {
#pragma omp for schedule(static) nowait
    for (long k = 0; k < n; ++k) {
      g.mass[k] = 0.0;
      g.mom[k].setZero();
      g.moff[k].setZero();
      g.force[k].setZero();
      if (gradients) g.vgrad[k].setZero();
    }
#pragma omp for schedule(static)
    for (long k = 0; k < nr; ++k) g.presence[k] = 0.0;
  }
}

template <int D>
template <Kernel K>
void Solver<D>::p2g_impl(bool mass_momentum, bool forces) {
  auto& g = sc_.grid;
  const auto& P = sc_.particles;
  const double inv_h = 1.0 / g.h, fs = sc_.settings.mass_scaling, a = half_width_;
  const long nn = g.nodes();
  const Vec<D> grav = sc_.settings.gravity;
  const bool gravity = grav.squaredNorm() > 0;
  const bool track_offsets = !sc_.bodies.empty();
  for (int phase = 0; phase < 2; ++phase) {
#pragma omp parallel for schedule(dynamic, 1)
    for (long s = phase; s < bins_.strips; s += 2) {
      const auto& members = bins_.members[static_cast<std::size_t>(s)];
      for (std::size_t k = 0; k < members.size(); ++k) {
        const std::uint32_t p = members[k];
        if (k + kPrefetchAhead < members.size()) {
          const std::uint32_t q = members[k + kPrefetchAhead];
          prefetch(&P.x[q], &P.v[q], &P.stress[q], &P.mass[q], &P.volume[q], &P.field[q]);
        }
        const Stencil<D> st = make_stencil<D, K>(P.x[p], g.origin, inv_h, a);
        const long off = P.field[p] * nn;
        const double m = P.mass[p] * fs;
        const Vec<D> mv = m * P.v[p];
        const Mat<D> sv = -P.volume[p] * in_plane<D>(P.stress[p]);
        const Vec<D> fext = P.mass[p] * grav;  // body force acts on the physical mass
        double* gm = g.mass.data() + off;
        Vec<D>* gp = g.mom.data() + off;
        Vec<D>* gf = g.force.data() + off;
        Vec<D>* go = g.moff.data() + off;
        Vec<D>* gg = g.vgrad.data() + off;
        const double vol = P.volume[p];
        const Vec<D> xs = P.x[p] - g.origin;
        if constexpr (D == 2) {
          // Tensor-product form of the 3 x 3 stencil, S = wx_i wy_j, G = (gx_i wy_j, wx_i gy_j):
          // per node row j the particle's contributions are scaled by the row factors once, then
          // by the x factors. The run-constant switches are tested once per row, so the node loops
          // are straight-line code; every nodal sum keeps its order.
          const auto& wx = st.w[0];
          const auto& gx = st.g[0];
          const long b0 = st.base[0] * g.stride[0] + st.base[1] * g.stride[1];
          for (int j = 0; j < 3; ++j) {
            const long r = b0 + j * g.stride[1];
            const double wy = st.w[1][j], gy = st.g[1][j];
            if (mass_momentum) {
              const double mj = wy * m;
              const Vec<D> pj = wy * mv;
              for (int i = 0; i < 3; ++i) {
                gm[r + i] += wx[i] * mj;
                gp[r + i] += wx[i] * pj;
              }
              if (track_offsets) {
                const Vec<D> oj = mj * xs;
                for (int i = 0; i < 3; ++i) go[r + i] += wx[i] * oj;
              }
              if (track_gradients_)
                for (int i = 0; i < 3; ++i) gg[r + i] += vol * Vec<D>(gx[i] * wy, wx[i] * gy);
            }
            if (forces) {
              const Vec<D> fa = wy * sv.col(0), fb = gy * sv.col(1);
              const Vec<D> fj = wy * fext;
              for (int i = 0; i < 3; ++i) {
                gf[r + i] += gx[i] * fa + wx[i] * fb;
                if (gravity) gf[r + i] += wx[i] * fj;
              }
            }
          }
        } else {
          // one node loop per quantity, the run-constant switches tested once per particle
          if (mass_momentum) {
            for_each_node<D>(st, g.stride, [&](long i, double S, const Vec<D>&) {
              gm[i] += S * m;
              gp[i] += S * mv;
            });
            if (track_offsets) for_each_node<D>(st, g.stride, [&](long i, double S, const Vec<D>&) { go[i] += (S * m) * xs; });
            if (track_gradients_) for_each_node<D>(st, g.stride, [&](long i, double, const Vec<D>& G) { gg[i] += vol * G; });
          }
          if (forces) {
            for_each_node<D>(st, g.stride, [&](long i, double S, const Vec<D>& G) {
              gf[i] += sv * G;
              if (gravity) gf[i] += S * fext;
            });
          }
        }
      }
    }
  }
  if (mass_momentum) {
    const long n = static_cast<long>(sc_.deformable_fields) * nn;
#pragma omp parallel for schedule(static)
    for (long k = 0; k < n; ++k) g.mom0[k] = g.mom[k];
  }
}

template <int D>
void Solver<D>::p2g(bool with_forces) {
  with_kernel(sc_.settings.kernel, [&](auto K) { this->template p2g_impl<decltype(K)::value>(true, with_forces); });
}

template <int D>
void Solver<D>::p2g_forces() {
  with_kernel(sc_.settings.kernel, [&](auto K) { this->template p2g_impl<decltype(K)::value>(false, true); });
}

template <int D>
template <Kernel K>
void Solver<D>::rigid_p2g_impl() {
  auto& g = sc_.grid;
  const double inv_h = 1.0 / g.h, a = half_width_;
  const long nn = g.nodes();
  for (std::size_t b = 0; b < sc_.bodies.size(); ++b) {
    auto& body = sc_.bodies[b];
    double* gm = g.presence.data() + (body.field - g.deformable) * nn;
    auto& cache = static_presence_[b];
    if (!body.moving() && !cache.empty()) {
      for (auto& [i, S] : cache) gm[i] += S;
      continue;
    }
    for (const auto& x : body.x) {
      const Stencil<D> st = make_stencil<D, K>(x, g.origin, inv_h, a);
      for_each_node<D>(st, g.stride, [&](long i, double S, const Vec<D>&) { gm[i] += S; });
    }
    if (!body.moving())
      for (long i = 0; i < nn; ++i)
        if (gm[i] > 0) cache.emplace_back(i, gm[i]);
  }
}

template <int D>
void Solver<D>::rigid_p2g() {
  with_kernel(sc_.settings.kernel, [&](auto K) { this->template rigid_p2g_impl<decltype(K)::value>(); });
}

template <int D>
void Solver<D>::contact(bool record) {
  if (!sc_.bodies.empty()) {
    RigidContactResult<D> r;
    rigid_contact<D>(sc_.grid, sc_.bodies, sc_.deformable_fields, t_ + (record ? dt_ : 0.0), mass_eps_, r);
    if (record) {
      for (std::size_t b = 0; b < sc_.bodies.size(); ++b) {
        sc_.bodies[b].impulse += r.impulse[b];
        sc_.bodies[b].work += r.work[b];
        dissipated_ += r.friction_work[b];
      }
    }
  }
  if (sc_.contact.fields < 2 || sc_.contact.all_weld()) {
    weld_fields<D>(sc_.grid, sc_.deformable_fields, mass_eps_);
  } else {
    const double friction = field_contact<D>(sc_.grid, sc_.contact, sc_.deformable_fields, dt_, mass_eps_,
                                             record ? &contact_tally_ : nullptr);
    if (record) dissipated_ += friction;
  }
}

template <int D>
void Solver<D>::grid_update() {
  auto& g = sc_.grid;
  const long n = static_cast<long>(sc_.deformable_fields) * g.nodes();
  const double dt = dt_;
#pragma omp parallel for schedule(static)
  for (long k = 0; k < n; ++k)
    if (g.mass[k] > mass_eps_) g.mom[k] += dt * g.force[k];
}

template <int D>
void Solver<D>::finalize_grid_velocities() {
  auto& g = sc_.grid;
  const long n = static_cast<long>(sc_.deformable_fields) * g.nodes();
#pragma omp parallel for schedule(static)
  for (long k = 0; k < n; ++k) {
    if (g.mass[k] > mass_eps_) {
      const double inv_m = 1.0 / g.mass[k];
      g.vel[k] = g.mom[k] * inv_m;
      g.dvel[k] = (g.mom[k] - g.mom0[k]) * inv_m;
    } else {
      g.vel[k].setZero();
      g.dvel[k].setZero();
    }
  }
}

// G2P: particle velocity by the FLIP/PIC blend, and per integrator:
//   USF: position update;  USL: position update and L from the updated nodal velocities;
//   MUSL: scatter of the updated particle momentum (positions move after the remap).
template <int D>
template <Kernel K>
void Solver<D>::g2p_impl() {
  auto& g = sc_.grid;
  auto& P = sc_.particles;
  const double inv_h = 1.0 / g.h, a = half_width_, dt = dt_, alpha = sc_.settings.flip;
  const double fs = sc_.settings.mass_scaling;
  const long nn = g.nodes();
  const Integrator integ = sc_.settings.integrator;
  const bool musl = integ == Integrator::musl;
  if (musl) {
    const long n = static_cast<long>(sc_.deformable_fields) * nn;
#pragma omp parallel for schedule(static)
    for (long k = 0; k < n; ++k) g.mom[k].setZero();
  }
  double vmax2 = 0;
  std::uint32_t bad = kNone, left = kNone;
  bool rebin = false;
  for (int phase = 0; phase < 2; ++phase) {
#pragma omp parallel for schedule(dynamic, 1) reduction(max : vmax2) reduction(min : bad, left) reduction(|| : rebin)
    for (long s = phase; s < bins_.strips; s += 2) {
      const auto& members = bins_.members[static_cast<std::size_t>(s)];
      for (std::size_t k = 0; k < members.size(); ++k) {
        const std::uint32_t p = members[k];
        if (k + kPrefetchAhead < members.size()) {
          const std::uint32_t q = members[k + kPrefetchAhead];
          prefetch(&P.x[q], &P.v[q], &P.L[q], &P.field[q]);
        }
        const Stencil<D> st = make_stencil<D, K>(P.x[p], g.origin, inv_h, a);
        const long off = P.field[p] * nn;
        const Vec<D>* gv = g.vel.data() + off;
        const Vec<D>* gdv = g.dvel.data() + off;
        Vec<D> vpic = Vec<D>::Zero(), dv = Vec<D>::Zero();
        Mat<D> L = Mat<D>::Zero();
        if constexpr (D == 2) {
          // Tensor-product form: per node row j the x-sums a_j = sum_i wx_i v_ij,
          // b_j = sum_i gx_i v_ij and c_j = sum_i wx_i dv_ij; then v = sum_j wy_j a_j,
          // dv = sum_j wy_j c_j and L = sum v (x) G = [sum_j wy_j b_j | sum_j gy_j a_j].
          const auto& wx = st.w[0];
          const auto& gx = st.g[0];
          const long b0 = st.base[0] * g.stride[0] + st.base[1] * g.stride[1];
          for (int j = 0; j < 3; ++j) {
            const long r = b0 + j * g.stride[1];
            const double wy = st.w[1][j];
            const Vec<D> aj = wx[0] * gv[r] + wx[1] * gv[r + 1] + wx[2] * gv[r + 2];
            const Vec<D> cj = wx[0] * gdv[r] + wx[1] * gdv[r + 1] + wx[2] * gdv[r + 2];
            vpic += wy * aj;
            dv += wy * cj;
            if (integ == Integrator::usl) {
              const Vec<D> bj = gx[0] * gv[r] + gx[1] * gv[r + 1] + gx[2] * gv[r + 2];
              L.col(0) += wy * bj;
              L.col(1) += st.g[1][j] * aj;
            }
          }
        } else if (integ == Integrator::usl) {
          for_each_node<D>(st, g.stride, [&](long i, double S, const Vec<D>& G) {
            vpic += S * gv[i];
            dv += S * gdv[i];
            L += gv[i] * G.transpose();
          });
        } else {
          for_each_node<D>(st, g.stride, [&](long i, double S, const Vec<D>&) {
            vpic += S * gv[i];
            dv += S * gdv[i];
          });
        }
        const Vec<D> vnew = alpha * (P.v[p] + dv) + (1.0 - alpha) * vpic;
        P.v[p] = vnew;
        if (musl) {
          const Vec<D> mv = (P.mass[p] * fs) * vnew;
          Vec<D>* gp = g.mom.data() + off;
          for_each_node<D>(st, g.stride, [&](long i, double S, const Vec<D>&) { gp[i] += S * mv; });
        } else {
          P.x[p] += dt * vpic;
          if (integ == Integrator::usl) P.L[p] = L;
          check_position<D>(g, bins_, inv_h, p, P.x[p], s, left, rebin);
        }
        const double sp2 = vnew.squaredNorm();  // sqrt once, of the maximum (monotonic)
        if (!(sp2 < 1e300)) bad = std::min(bad, p);
        vmax2 = std::max(vmax2, sp2);
      }
    }
  }
  vmax_ = std::sqrt(vmax2);
  if (!musl) {
    left_grid_ = left;
    rebin_ = rebin;
  }
  if (bad != kNone)
    throw InstabilityError(fmt::format("step {}: particle {} (material '{}') has a non-finite velocity",
                                       steps_, bad, sc_.material_names[P.material[bad]]));
}

template <int D>
void Solver<D>::g2p() {
  with_kernel(sc_.settings.kernel, [&](auto K) { this->template g2p_impl<decltype(K)::value>(); });
}

// MUSL: L from the remapped nodal velocities, then the position update with the step's velocities,
// both with the shape functions of the start of the step.
template <int D>
template <Kernel K>
void Solver<D>::remap_gradient_impl() {
  auto& g = sc_.grid;
  auto& P = sc_.particles;
  const double inv_h = 1.0 / g.h, a = half_width_, dt = dt_;
  const long nn = g.nodes();
  const long nd = static_cast<long>(sc_.deformable_fields) * nn;
#pragma omp parallel for schedule(static)
  for (long k = 0; k < nd; ++k)
    g.dvel[k] = g.mass[k] > mass_eps_ ? Vec<D>(g.mom[k] / g.mass[k]) : Vec<D>::Zero();
  // strip by strip (a gather: no parity phases), so that the end-of-step check knows each
  // particle's strip
  std::uint32_t left = kNone;
  bool rebin = false;
#pragma omp parallel for schedule(dynamic, 1) reduction(min : left) reduction(|| : rebin)
  for (long s = 0; s < bins_.strips; ++s) {
    for (const std::uint32_t p : bins_.members[static_cast<std::size_t>(s)]) {
      const Stencil<D> st = make_stencil<D, K>(P.x[p], g.origin, inv_h, a);
      const long off = P.field[p] * nn;
      const Vec<D>* gv = g.vel.data() + off;
      const Vec<D>* gr = g.dvel.data() + off;
      Vec<D> vpic = Vec<D>::Zero();
      Mat<D> L = Mat<D>::Zero();
      for_each_node<D>(st, g.stride, [&](long i, double S, const Vec<D>& G) {
        vpic += S * gv[i];
        L += gr[i] * G.transpose();
      });
      P.L[p] = L;
      P.x[p] += dt * vpic;
      check_position<D>(g, bins_, inv_h, p, P.x[p], s, left, rebin);
    }
  }
  left_grid_ = left;
  rebin_ = rebin;
}

template <int D>
void Solver<D>::remap_velocity_gradient() {
  with_kernel(sc_.settings.kernel, [&](auto K) { this->template remap_gradient_impl<decltype(K)::value>(); });
}

template <int D>
template <Kernel K>
void Solver<D>::velocity_gradient_impl() {
  auto& g = sc_.grid;
  auto& P = sc_.particles;
  const double inv_h = 1.0 / g.h, a = half_width_;
  const long nn = g.nodes();
  const long nd = static_cast<long>(sc_.deformable_fields) * nn;
#pragma omp parallel for schedule(static)
  for (long k = 0; k < nd; ++k)
    g.vel[k] = g.mass[k] > mass_eps_ ? Vec<D>(g.mom[k] / g.mass[k]) : Vec<D>::Zero();
  const long np = static_cast<long>(P.size());
#pragma omp parallel for schedule(static)
  for (long p = 0; p < np; ++p) {
    const Stencil<D> st = make_stencil<D, K>(P.x[p], g.origin, inv_h, a);
    const Vec<D>* gv = g.vel.data() + P.field[p] * nn;
    Mat<D> L = Mat<D>::Zero();
    for_each_node<D>(st, g.stride, [&](long i, double, const Vec<D>& G) { L += gv[i] * G.transpose(); });
    P.L[p] = L;
  }
}

template <int D>
void Solver<D>::velocity_gradient() {
  with_kernel(sc_.settings.kernel, [&](auto K) { this->template velocity_gradient_impl<decltype(K)::value>(); });
}

// Kinematics (F, J, V) and the material laws, one call per material per chunk of its batch.
template <int D>
void Solver<D>::update_stress() {
  auto& P = sc_.particles;
  const double dt = dt_;
  constexpr long chunk = 2048;
  double cmax = 0;
  for (std::size_t m = 0; m < sc_.materials.size(); ++m) {
    auto& st = sc_.material_state[m];
    const auto& mat = *sc_.materials[m];
    const long n = static_cast<long>(st.index.size());
    const long nchunks = (n + chunk - 1) / chunk;
    const int hs = mat.history_size();
    std::vector<MaterialStepResult> res(static_cast<std::size_t>(nchunks));
    std::vector<std::uint32_t> bad(static_cast<std::size_t>(nchunks), kNone);
#pragma omp parallel for schedule(dynamic, 1)
    for (long c = 0; c < nchunks; ++c) {
      const long b = c * chunk, e = std::min(n, b + chunk);
      std::uint32_t worst = kNone;
      for (long k = b; k < e; ++k) {
        const std::uint32_t p = st.index[static_cast<std::size_t>(k)];
        P.F[p] = (Mat<D>::Identity() + dt * P.L[p]) * P.F[p];
        const double J = P.F[p].determinant();
        if (!(J > 0)) worst = std::min(worst, p);
        P.volume[p] = J * P.volume0[p];
      }
      if (worst == kNone) {
        MaterialBatch<D> batch;
        batch.index = std::span<const std::uint32_t>(st.index.data() + b, static_cast<std::size_t>(e - b));
        batch.L = P.L.data();
        batch.F = P.F.data();
        batch.mass = P.mass.data();
        batch.volume = P.volume.data();
        batch.volume0 = P.volume0.data();
        batch.stress = P.stress.data();
        batch.history = st.history.data() + b * hs;
        batch.dt = dt;
        res[static_cast<std::size_t>(c)] = mat.update(batch);
        for (long k = b; k < e; ++k) {
          const std::uint32_t p = st.index[static_cast<std::size_t>(k)];
          const Sym3& s = P.stress[p];
          if (!std::isfinite(s.xx + s.yy + s.zz + s.xy + s.yz + s.zx)) worst = std::min(worst, p);
        }
      }
      bad[static_cast<std::size_t>(c)] = worst;
    }
    for (long c = 0; c < nchunks; ++c) {
      const std::uint32_t p = bad[static_cast<std::size_t>(c)];
      if (p != kNone) {
        const double J = P.F[p].determinant();
        throw InstabilityError(fmt::format(
            "step {} (t = {:.6g} s): particle {} of material '{}' at ({:.6g}, {:.6g}) m has {}",
            steps_, t_, p, sc_.material_names[m], P.x[p][0], P.x[p][1],
            J > 0 ? "a non-finite stress" : fmt::format("J = {:.4g} <= 0 (inverted)", J)));
      }
      const auto& r = res[static_cast<std::size_t>(c)];
      internal_ += r.stress_work;
      dissipated_ += r.dissipated;
      cmax = std::max(cmax, r.max_wave_speed);
    }
  }
  cmax_ = cmax;
}

template <int D>
void Solver<D>::advance_bodies() {
  for (auto& b : sc_.bodies)
    if (b.moving()) b.move_to(t_);
  // The positions were checked where they were updated (G2P, or the MUSL remap).
  const auto& P = sc_.particles;
  const std::uint32_t bad = left_grid_;
  if (bad != kNone)
    throw InstabilityError(fmt::format("step {} (t = {:.6g} s): particle {} of material '{}' left the grid at ({:.6g}, {:.6g}) m",
                                       steps_, t_, bad, sc_.material_names[P.material[bad]], P.x[bad][0], P.x[bad][1]));
  if (rebin_) {
    rebuild_bins();
    rebin_ = false;
  }
}

template <int D>
double Solver<D>::kinetic_energy() const {
  const auto& P = sc_.particles;
  const double fs = sc_.settings.mass_scaling;
  return ordered_reduce(static_cast<long>(P.size()), 0.0, [&](long b, long e) {
    double s = 0;
    for (long p = b; p < e; ++p) s += 0.5 * fs * P.mass[p] * P.v[p].squaredNorm();
    return s;
  });
}

template class Solver<2>;
template class Solver<3>;

}  // namespace pbx
