// The fused particle pass of the USL step: G2P -> stress update -> P2G of the next step, run chunk
// by chunk over each strip's particles (grid/strip_bins.hpp). Each particle's data are read from
// memory once per step instead of once per stage, and a step has two parallel particle loops
// instead of five. The stages are the same as in the unfused step, in the same order for every
// particle, calling the same kernels (solver/transfer.hpp, the material plug-ins):
//   1. G2P at the start-of-step position: FLIP/PIC velocity, position, velocity gradient L;
//      where the particle is now (home strip, stray, outside the grid);
//   2. stress update: F, J and volume, then each material updates its part of the chunk, which is
//      a contiguous part of its batch (particles are stored strip by strip, batches in storage
//      order): one virtual call per material per chunk, never one per particle;
//   3. P2G of the next step at the new position into the freshly reset nodal sums (G2P reads
//      only the final velocities vel and dvel, P2G writes mass, momentum and force, so the two
//      never touch the same arrays). Strays wait and scatter serially after the two phases.
// The P2G sums therefore arrive at every node in the order of the stand-alone P2G stage (the one
// a restart makes), and 1 or N threads give the same bits.
#include <array>
#include <chrono>
#include <cmath>
#include <stdexcept>

#include <fmt/format.h>

#include "core/error.hpp"
#include "solver/material_batch.hpp"
#include "solver/solver.hpp"
#include "solver/kinematics.hpp"

namespace pbx {

template <int D>
void Solver<D>::g2p_update_p2g() {
  with_kernel(sc_.settings.kernel, [&](auto K) { this->template particle_pass_impl<decltype(K)::value>(); });
}

template <int D>
template <Kernel K>
void Solver<D>::particle_pass_impl() {
  auto& g = sc_.grid;
  auto& P = sc_.particles;
  const double inv_h = 1.0 / g.h, dt = dt_, alpha = sc_.settings.flip;
  const HalfWidth a(half_width_);
  const long nn = g.nodes();
  const std::size_t nm = sc_.materials.size();
  Scatter<D> scatter_one = scatter(true, true);
  scatter_one.offset_bases = masks_.offset_bases();
  scatter_one.contact_bases = masks_.contact_bases();
  // per chunk, summed in chunk order after the pass (thread-count independent)
  std::vector<MaterialStepResult> results(static_cast<std::size_t>(chunk_begin_.back()));
  std::vector<double> chunk_dissipated(results.size() * nm, 0.0);  // [chunk][material]
  double vmax2 = 0, moved = 0;  // moved: the largest step of a particle along an axis, cells
  std::uint32_t bad_v = kNone, bad_s = kNone, left = kNone;
  long strays = 0;
  // thread seconds in each part of the pass, to split its wall time between the stages
  using Clock = StageClock::Clock;
  const auto wall0 = Clock::now();
  double t_g2p = 0, t_stress = 0, t_p2g = 0;
  auto seconds = [](Clock::time_point a, Clock::time_point b) { return std::chrono::duration<double>(b - a).count(); };
  if (exchange_) exchange_->start_scatter();
  for (int part = 0; part < 4; ++part) {  // each phase's lead strips, then its others (StripBins::visit_order)
    if (exchange_ && part % 2 == 0) exchange_->before_lead(part / 2);
    const std::vector<long>& order = bins_.visit_order(part);
#pragma omp parallel for schedule(dynamic, 1) if (!order.empty()) reduction(max : vmax2, moved) reduction(min : bad_v, bad_s, left) reduction(+ : strays, t_g2p, t_stress, t_p2g)
    for (std::size_t k = 0; k < order.size(); ++k) {
      const long s = order[k];
      const long b = bins_.begin[static_cast<std::size_t>(s)], e = bins_.begin[static_cast<std::size_t>(s + 1)];
      std::vector<long> cursor(nm), count(nm);  // batch position of the chunk's first particle, per material
      for (std::size_t m = 0; m < nm; ++m) cursor[m] = batch_begin_[m][static_cast<std::size_t>(s)];
      for (long c0 = b; c0 < e; c0 += kPassChunk) {
        const long c1 = std::min(e, c0 + kPassChunk);
        std::array<std::uint8_t, kPassChunk> place;

        // 1. G2P
        const auto c_start = Clock::now();
        for (long q = c0; q < c1; ++q) {
          const auto p = static_cast<std::uint32_t>(q);
          const Stencil<D> st = make_stencil<D, K>(P.x[p], g.origin, inv_h, a, &g.clamped);
          const Gathered<D> r = gather<D>(g, P.field[p] * nn, st, true);
          const Vec<D> vnew = alpha * (P.v[p] + r.dv) + (1.0 - alpha) * r.vpic;
          P.v[p] = vnew;
          const Vec<D> dx = dt * r.vpic;
          P.x[p] += dx;
          moved = std::max(moved, dx.cwiseAbs().maxCoeff() * inv_h);
          P.L[p] = r.L;
          place[static_cast<std::size_t>(q - c0)] = bins_.relocate<D>(g, inv_h, P.x[p], s, p, left, strays);
          const double sp2 = vnew.squaredNorm();  // sqrt once, of the maximum (monotonic)
          if (!(sp2 < 1e300)) bad_v = std::min(bad_v, p);
          vmax2 = std::max(vmax2, sp2);
        }

        // 2. stress update: kinematics, then the materials
        const auto c_g2p = Clock::now();
        t_g2p += seconds(c_start, c_g2p);
        std::uint32_t worst = kNone;
        std::fill(count.begin(), count.end(), 0L);
        for (long p = c0; p < c1; ++p) {
          P.F[p] = advance_deformation_gradient<D>(P.F[p], P.L[p], dt);
          const double J = P.F[p].determinant();
          if (!(J > 0)) worst = std::min(worst, static_cast<std::uint32_t>(p));
          P.volume[p] = J * P.volume0[p];
          ++count[static_cast<std::size_t>(P.material[p])];
        }
        if (worst == kNone) {
          const std::size_t chunk =
              static_cast<std::size_t>(chunk_begin_[static_cast<std::size_t>(s)] + (c0 - b) / kPassChunk);
          MaterialStepResult& res = results[chunk];
          for (std::size_t m = 0; m < nm; ++m) {
            if (count[m] == 0) continue;
            auto& state = sc_.material_state[m];
            const MaterialBatch<D> batch =
                material_batch<D>(P, state, sc_.materials[m]->history_size(), cursor[m], count[m], dt);
            const MaterialStepResult r = sc_.materials[m]->update(batch);
            res.stress_work += r.stress_work;
            res.dissipated += r.dissipated;
            chunk_dissipated[chunk * nm + m] += r.dissipated;
            res.max_wave_speed = std::max(res.max_wave_speed, r.max_wave_speed);
          }
          for (long p = c0; p < c1; ++p) {
            const Sym3& st = P.stress[p];
            if (!std::isfinite(st.xx + st.yy + st.zz + st.xy + st.yz + st.zx))
              worst = std::min(worst, static_cast<std::uint32_t>(p));
          }
        }
        for (std::size_t m = 0; m < nm; ++m) cursor[m] += count[m];
        bad_s = std::min(bad_s, worst);
        const auto c_stress = Clock::now();
        t_stress += seconds(c_g2p, c_stress);
        if (worst != kNone) continue;  // the run stops after the pass

        // 3. P2G of the next step
        for (long q = c0; q < c1; ++q)
          if (place[static_cast<std::size_t>(q - c0)] == StripBins::kHome)
            scatter_one(static_cast<std::uint32_t>(q), make_stencil<D, K>(P.x[q], g.origin, inv_h, a, &g.clamped));
        t_p2g += seconds(c_stress, Clock::now());
      }
    }
    if (exchange_ && part % 2 == 0) exchange_->after_lead(part / 2);
  }
  if (exchange_) exchange_->finish_scatter();
  const auto wall1 = Clock::now();
  clock_.split_pass(seconds(wall0, wall1), t_g2p, t_stress, t_p2g);
  bins_.collect_strays(strays);
  double cmax = 0;
  for (const auto& r : results) cmax = std::max(cmax, r.max_wave_speed);
  vmax_ = std::sqrt(vmax2);
  bool strays_anywhere = !bins_.strays.empty();
  if (exchange_) {
    // One collective for what every rank must decide as one: a full P2G again (a collective
    // pass), a stop, the strays' pass, and the next step's size (the largest of each over the
    // ranks; sqrt is monotonic, so the largest speed is the one of the largest square).
    const bool bad = bad_v != kNone || bad_s != kNone || left != kNone;
    std::array<double, 5> any = {moved, bad ? 1.0 : 0.0, strays_anywhere ? 1.0 : 0.0, vmax_, cmax};
    exchange_->max_each(any);
    moved = any[0];
    strays_anywhere = any[2] > 0.0;
    // Every rank stops here, before any other collective step: the rank of the culprit with its
    // message (a particle leaving the grid too, which one process reports at the end of the step).
    if (any[1] > 0.0) {
      if (bad_v != kNone)
        throw InstabilityError(fmt::format("step {}: particle {} (material '{}') has a non-finite velocity", steps_,
                                           bad_v, sc_.material_names[P.material[bad_v]]));
      if (bad_s != kNone) stop_on_bad_stress(bad_s);
      if (left != kNone) stop_on_left_grid(left);
      throw InstabilityError(fmt::format("step {}: another rank of the run stopped (its message says why)", steps_));
    }
    vmax_ = any[3];
    cmax = any[4];
  }
  scatter_strays([&](std::uint32_t p) { scatter_one(p, make_stencil<D, K>(P.x[p], g.origin, inv_h, a, &g.clamped)); },
                 strays_anywhere);
  clock_.add(Stage::p2g, seconds(wall1, Clock::now()));
  left_grid_ = left;
  // A particle that moved a cell or more may have met a field the contact mask did not foresee:
  // the next step's sums are made again in full (never seen in a stable run; the order of the
  // stand-alone P2G is the pass's, so the bits are the same as an unmasked pass).
  if (masks_.contact_valid() && !(moved < 1.0) && bad_v == kNone && bad_s == kNone) {
    masks_.drop_contact();
    reset_grid();
    p2g(true);
  }

  if (bad_v != kNone)
    throw InstabilityError(fmt::format("step {}: particle {} (material '{}') has a non-finite velocity", steps_, bad_v,
                                       sc_.material_names[P.material[bad_v]]));
  if (bad_s != kNone) stop_on_bad_stress(bad_s);
  cmax_ = cmax;
  // The chunks' energies in chunk order, for the books. A decomposed run's ranks hold contiguous
  // ranges of the chunks (chunks never straddle strips), so every rank's, in rank order, are the
  // run's in order.
  std::vector<double> sums;
  sums.reserve(results.size() * (2 + nm));
  for (std::size_t c = 0; c < results.size(); ++c) {
    sums.push_back(results[c].stress_work);
    sums.push_back(results[c].dissipated);
    sums.insert(sums.end(), chunk_dissipated.begin() + static_cast<long>(c * nm),
                chunk_dissipated.begin() + static_cast<long>((c + 1) * nm));
  }
  books_.add(std::move(sums), [this, nm](const std::vector<double>& all) {
    for (std::size_t k = 0; k < all.size(); k += 2 + nm) {
      internal_ += all[k];
      dissipated_ += all[k + 1];
      for (std::size_t m = 0; m < nm; ++m) dissipated_material_[m] += all[k + 2 + m];
    }
  });
}

template void Solver<2>::g2p_update_p2g();
template void Solver<3>::g2p_update_p2g();

}  // namespace pbx
