#include "solver/solver.hpp"
#include "solver/kinematics.hpp"

#include <algorithm>
#include <cmath>
#include <iterator>
#include <limits>
#include <stdexcept>

#include <fmt/format.h>
#include <omp.h>

#include "contact/field_contact.hpp"
#include "contact/law_binder_layer.hpp"
#include "contact/rigid_contact.hpp"
#include "core/error.hpp"
#include "core/parallel.hpp"
#include "solver/material_batch.hpp"

namespace pbx {

template <int D>
Solver<D>::Solver(Scene<D>& scene) : sc_(scene) {
  order_by_strip(sc_);  // a no-op for scenes from build_scene (already ordered)
  const auto& P = sc_.particles;
  setup_strips();
  double msum = 0;
  for (double m : P.mass) msum += m;
  mass_eps_ = 1e-20 * sc_.settings.mass_scaling * msum / static_cast<double>(std::max<std::size_t>(1, P.size()));
  half_width_ = 0.5 / sc_.settings.ppc;
  for (auto& m : sc_.materials) cmax_ = std::max(cmax_, m->initial_wave_speed());
  for (auto& v : P.v) vmax_ = std::max(vmax_, v.norm());
  track_gradients_ = sc_.deformable_fields > 1;
  contact_tally_ = ContactTally<D>(sc_.deformable_fields);
  bins_.deferred = &books_;
  dissipated_material_.assign(sc_.materials.size(), 0.0);
  if (!sc_.layer_data.bonds.empty()) {
    // The pairs are explicit springs: stable while omega dt < 2 for their stiffest mode. Bounded per
    // particle (Gershgorin) by omega^2 <= sum over its pairs of k (1/m_p + 1/m_q), with k the law's
    // largest normal modulus over the run (its table starts at the instantaneous one); half of 2/omega.
    bond_dp_.assign(P.size(), Vec<D>::Zero());
    std::vector<double> w2(P.size(), 0.0);
    const double fs = sc_.settings.mass_scaling;
    for (const auto& b : sc_.layer_data.bonds) {
      const auto& L = sc_.contact.layers[static_cast<std::size_t>(b.layer)];
      const double kmax = b.coef * std::max(*std::max_element(L.normal.begin(), L.normal.end()),
                                            *std::max_element(L.shear.begin(), L.shear.end()));
      const double c = kmax * (1.0 / (fs * P.mass[b.p]) + 1.0 / (fs * P.mass[b.q]));
      w2[b.p] += c, w2[b.q] += c;
    }
    const double w2max = *std::max_element(w2.begin(), w2.end());
    if (w2max > 0.0) bond_dt_ = 1.0 / std::sqrt(w2max);
  }
}

template <int D>
void Solver<D>::restore(const State& s) {
  t_ = s.t;
  dt_ = s.dt;
  cmax_ = s.cmax;
  vmax_ = s.vmax;
  internal_ = s.internal;
  dissipated_ = s.dissipated;
  // a checkpoint without the parts: the friction holds what the materials' parts do not
  std::fill(dissipated_material_.begin(), dissipated_material_.end(), 0.0);
  if (s.dissipated_by_material.size() == dissipated_material_.size()) dissipated_material_ = s.dissipated_by_material;
  friction_ = s.dissipated_by_material.empty() ? s.dissipated : s.friction;
  steps_ = s.steps;
  for (auto& b : sc_.bodies) b.move_to(t_);
  left_grid_ = kNone;
  grid_primed_ = false;  // the restored particles make the next P2G afresh
  locate_particles();
}

// Home strips are the storage ranges of the (strip-ordered) particles at construction; they stay
// fixed for the run, and so do the batch positions where each strip's particles of each material
// begin (the fused pass hands a material a contiguous part of its batch).
template <int D>
void Solver<D>::setup_strips() {
  const auto& P = sc_.particles;
  const long np = static_cast<long>(P.size());
  const double inv_h = 1.0 / sc_.grid.h;
  bins_.setup(sc_.grid.n[0] - 1);
  bins_.begin.assign(static_cast<std::size_t>(bins_.strips + 1), np);
  for (long p = np - 1; p >= 0; --p)
    bins_.begin[static_cast<std::size_t>(bins_.strip_of((P.x[p][0] - sc_.grid.origin[0]) * inv_h))] = p;
  for (long s = bins_.strips - 1; s >= 0; --s)
    bins_.begin[static_cast<std::size_t>(s)] =
        std::min(bins_.begin[static_cast<std::size_t>(s)], bins_.begin[static_cast<std::size_t>(s + 1)]);
  bins_.stray.assign(P.size(), 0);
  bins_.strays.clear();
  batch_begin_.assign(sc_.materials.size(), {});
  for (std::size_t m = 0; m < sc_.materials.size(); ++m) {
    const auto& index = sc_.material_state[m].index;
    for (long s = 0; s <= bins_.strips; ++s)
      batch_begin_[m].push_back(std::lower_bound(index.begin(), index.end(),
                                                 static_cast<std::uint32_t>(bins_.begin[static_cast<std::size_t>(s)])) -
                                index.begin());
  }
  chunk_begin_.assign(1, 0);
  for (long s = 0; s < bins_.strips; ++s) {
    const long n = bins_.begin[static_cast<std::size_t>(s + 1)] - bins_.begin[static_cast<std::size_t>(s)];
    chunk_begin_.push_back(chunk_begin_.back() + (n + kPassChunk - 1) / kPassChunk);
  }
  locate_particles();
}

// f(p) for every particle in its home strip, in the scatter's parity phases (grid/strip_bins.hpp:
// race-free, the sum order at every node fixed by storage order and positions, whatever the thread
// count), each phase led by the rank's strips at its cuts in a decomposed run, whose exchange
// completes the shared node lines meanwhile (solver/scatter_exchange.hpp). The strays follow
// (scatter_strays).
template <int D>
template <class F>
void Solver<D>::scatter_home(F&& f) {
  if (exchange_) exchange_->start_scatter();
  for (int part = 0; part < 4; ++part) {
    if (exchange_ && part % 2 == 0) exchange_->before_lead(part / 2);
    const std::vector<long>& order = bins_.visit_order(part);
#pragma omp parallel for schedule(dynamic, 1) if (!order.empty())
    for (std::size_t k = 0; k < order.size(); ++k) {
      const long s = order[k];
      for (long p = bins_.begin[static_cast<std::size_t>(s)]; p < bins_.begin[static_cast<std::size_t>(s + 1)]; ++p)
        if (!bins_.stray[static_cast<std::size_t>(p)]) f(p);
    }
    if (exchange_ && part % 2 == 0) exchange_->after_lead(part / 2);
  }
  if (exchange_) exchange_->finish_scatter();
}

// Stray flags after positions were set from outside the step (construction, restart).
template <int D>
void Solver<D>::locate_particles() {
  const auto& P = sc_.particles;
  const double inv_h = 1.0 / sc_.grid.h;
  long count = 0;
  for (long s = 0; s < bins_.strips; ++s)
    for (long p = bins_.begin[static_cast<std::size_t>(s)]; p < bins_.begin[static_cast<std::size_t>(s + 1)]; ++p) {
      const auto place = bins_.locate<D>(sc_.grid, inv_h, P.x[p], s);
      bins_.stray[static_cast<std::size_t>(p)] = place == StripBins::kStray;
      count += place == StripBins::kStray;
    }
  bins_.collect_strays(count);
}

template <int D>
void Solver<D>::set_scatter_exchange(ScatterExchange* exchange, double mass_threshold) {
  exchange_ = exchange;
  mass_eps_ = mass_threshold;
  // the sums over nodes and particles take this rank's strips and gather the others' (StripBins::fold)
  bins_.own_lo = exchange_ ? exchange_->first_strip() : 0;
  bins_.own_hi = exchange_ ? exchange_->end_strip() : bins_.strips;
  bins_.visit_lo = std::max(0L, bins_.own_lo - 2);
  bins_.visit_hi = std::min(bins_.strips, bins_.own_hi + 2);
  bins_.gather = exchange_;
  // the books' sums wait for one gather at the next history row (core/parallel.hpp, DeferredSums)
  books_.gather_through(exchange_);
  // the strips at the rank's cuts lead their phases (their lines go to the neighbours)
  std::vector<long> lead;
  if (exchange_ && bins_.own_lo > 0) lead.push_back(bins_.own_lo);
  if (exchange_ && bins_.own_hi < bins_.strips) lead.push_back(bins_.own_hi - 1);
  bins_.lead_with(lead);
  if (exchange_) vmax_ = exchange_->max(vmax_);
}

// The stray zones of a decomposed run reach one strip beyond a cut (docs/architecture.md, "One
// run over many ranks", item 4): a stray further from its home strip stops every rank (moving
// particles between ranks is not built).
template <int D>
std::pair<long, long> Solver<D>::refuse_far_strays() {
  const auto& P = sc_.particles;
  const double inv_h = 1.0 / sc_.grid.h;
  std::uint32_t far = kNone;
  long lo = sc_.grid.n[0], hi = -1;  // none
  for (const std::uint32_t p : bins_.strays) {
    const long home =
        std::upper_bound(bins_.begin.begin(), bins_.begin.end(), static_cast<long>(p)) - bins_.begin.begin() - 1;
    const double x = (P.x[p][0] - sc_.grid.origin[0]) * inv_h;
    if (std::abs(bins_.strip_of(x) - home) > 1 && far == kNone) far = p;
    // a particle in cell c reaches node lines c - 1 ... c + 2 (a stray is inside the grid)
    const long cell = static_cast<long>(std::floor(x));
    lo = std::min(lo, cell - 1);
    hi = std::max(hi, cell + 2);
  }
  if (exchange_->max(far == kNone ? 0.0 : 1.0) > 0.0)
    throw std::runtime_error(
        far == kNone
            ? fmt::format("step {}: another rank's particle moved beyond the strip next to its home strip", steps_)
            : fmt::format("step {}: particle {} (material '{}') moved beyond the strip next to its home strip "
                          "({} cells wide), which a run over several MPI ranks does not follow yet (its "
                          "particles stay on their rank); run it on one process",
                          steps_, far, sc_.material_names[P.material[far]], bins_.width));
  return {lo, hi};
}

template <int D>
double Solver<D>::stable_time_step() const {
  // a rigid body (the punch) must not cross a cell in a step either: its final speed counts like
  // a particle's (a punch at 3 km/s inverted the particles it hit, reported without the cause)
  double body_speed = 0;
  for (const auto& b : sc_.bodies) body_speed = std::max(body_speed, b.velocity.norm());
  const double c = cmax_ / std::sqrt(sc_.settings.mass_scaling) + std::max(vmax_, body_speed);
  return std::min(sc_.settings.cfl * sc_.grid.h / c, bond_dt_);
}

// ------------------------------------------------------------------------------------- the step
template <int D>
void Solver<D>::step(double max_dt) {
  if (exchange_ && sc_.settings.integrator != Integrator::usl)
    throw std::logic_error("Solver::step: a run decomposed over ranks steps with USL only (issue 28)");
  dt_ = std::min(stable_time_step(), max_dt);
  rigid_p2g();
  switch (sc_.settings.integrator) {
    case Integrator::usf:
      reset_grid();
      p2g(false);
      keep_interpolated_momentum();
      contact(true);
      velocity_gradient();
      update_stress();
      p2g_forces();
      grid_update();
      final_contact();
      finalize_grid_velocities();
      keep_contact_velocities();  // for the next step's velocity gradient
      g2p();
      break;
    case Integrator::usl:
      if (!grid_primed_) {  // first step (or after a restart); later, the last particle pass did it
        reset_grid();
        p2g(true);
      }
      keep_interpolated_momentum();
      contact(true);
      grid_update();
      contact(true, true);
      finalize_grid_velocities();
      mark_contact_bases();  // from this step's masses, before they are reset
      reset_grid();          // the nodal sums of the next step start here (G2P reads only vel, dvel)
      g2p_update_p2g();      // G2P -> stress update -> next step's P2G, chunk by chunk
      grid_primed_ = true;
      break;
    case Integrator::musl:
      reset_grid();
      p2g(true);
      keep_interpolated_momentum();
      contact(true);
      grid_update();
      final_contact();
      finalize_grid_velocities();
      keep_contact_velocities();
      g2p();  // also maps the updated particle momenta back to the grid
      contact(false);
      // where the final contact pass acted, L takes the step's final velocity (final_contact)
      for (const auto& [k, v] : contact_vel_) sc_.grid.mom[k] = sc_.grid.mass[k] * v;
      contact_vel_.clear();
      remap_velocity_gradient();
      update_stress();
      break;
  }
  t_ += dt_;
  ++steps_;
  advance_bodies();
}

// ------------------------------------------------------------------------------------- stages
// Zeroes the nodal sums of the deformable fields (the rigid presence is rigid_p2g's own). With a C1
// shape function (uGIMP, bspline2) a particle adds to a node's sums only where its weight is not
// zero, since the weight's gradient vanishes with it; a node entry whose mass is exactly zero has
// therefore received nothing since it was last zeroed, and is left as it is. A colour field
// covers a tenth of the paper specimen's nodes, so most entries are skipped (the linear kernel's
// gradient jumps at a node, and it zeroes everything).
template <int D>
void Solver<D>::reset_grid() {
  const auto timer = clock_.scope(Stage::reset);
  auto& g = sc_.grid;
  const bool gradients = track_gradients_, layers = sc_.layer_data.on();
  auto& sums = sc_.layer_data.sums;
  const bool all = sc_.settings.kernel == Kernel::linear;
  double* mass = g.mass.data();
  Vec<D>*mom = g.mom.data(), *moff = g.moff.data(), *force = g.force.data(), *vgrad = g.vgrad.data();
  for_each_visited_run([&](long b, long e) {
    for (long k = b; k < e; ++k) {
      if (!all && mass[k] == 0.0) continue;
      mass[k] = 0.0;
      mom[k].setZero();
      moff[k].setZero();
      force[k].setZero();
      if (gradients) vgrad[k].setZero();
      if (layers) sums.zero(static_cast<std::size_t>(k));
    }
  });
}

// The node-fields of the deformable fields on the node columns this process's node stages visit
// (StripBins::visit_lo ... visit_hi), as runs f(begin, end) of consecutive indices: all of them in
// one process (a block per thread); a decomposed run's rank leaves out the columns that neither its
// particles nor its exchanges reach, which hold nothing on it (each rank keeps the whole grid, and
// these loops cost every rank the whole grid's time before: docs/performance/engine.md, "Weak
// scaling").
template <int D>
template <class F>
void Solver<D>::for_each_visited_run(F&& f) {
  const auto& g = sc_.grid;
  const long nn = g.nodes(), nf = sc_.deformable_fields;
  if (bins_.visit_lo == 0 && bins_.visit_hi == bins_.strips) {
    const long n = nf * nn;
#pragma omp parallel
    {
      const long t = omp_get_thread_num(), nt = omp_get_num_threads();
      f(n * t / nt, n * (t + 1) / nt);
    }
    return;
  }
  const long nx = g.n[0], lines = nf * (nn / nx);  // node lines along x, of every field
  const long c0 = bins_.visit_lo == 0 ? 0 : bins_.visit_lo * bins_.width;
  const long c1 = bins_.visit_hi >= bins_.strips ? nx : std::min(nx, bins_.visit_hi * bins_.width);
#pragma omp parallel for schedule(static)
  for (long l = 0; l < lines; ++l) f(l * nx + c0, l * nx + c1);
}

// The momentum as interpolated, before contact and forces change it: the base of the FLIP
// increment.
template <int D>
void Solver<D>::keep_interpolated_momentum() {
  const auto timer = clock_.scope(Stage::grid_update);
  auto& g = sc_.grid;
  const Vec<D>* mom = g.mom.data();
  Vec<D>* mom0 = g.mom0.data();
  for_each_visited_run([&](long b, long e) { std::copy(mom + b, mom + e, mom0 + b); });
}

template <int D>
Scatter<D> Solver<D>::scatter(bool mass_momentum, bool forces) {
  const Vec<D> grav = sc_.settings.gravity;
  // Mass-centre offsets serve the rigid-body contact gate, the field position check
  // (contact.position_check), which without them would compare zero offsets and never fire, and
  // the binder_layer jump (its fields' mass centres), which without them would read a fixed jump.
  const bool layers = sc_.layer_data.on();
  const bool for_contact = sc_.contact.position_cutoff > 0.0 || layers;
  const bool offsets = !sc_.bodies.empty() || for_contact;
  Scatter<D> s{sc_.grid,
               sc_.particles,
               sc_.settings.mass_scaling,
               grav,
               grav.squaredNorm() > 0,
               mass_momentum,
               forces,
               offsets,
               track_gradients_,
               layers,
               for_contact};
  s.layer_data = &sc_.layer_data;
  return s;
}

// Even strips in parallel, then odd strips, then the strays serially (grid/strip_bins.hpp).
template <int D>
template <Kernel K>
void Solver<D>::p2g_impl(bool mass_momentum, bool forces) {
  const auto& g = sc_.grid;
  const auto& P = sc_.particles;
  const double inv_h = 1.0 / g.h;
  const HalfWidth a(half_width_);
  const Scatter<D> scatter_one = scatter(mass_momentum, forces);
  scatter_home([&](long p) {
    scatter_one(static_cast<std::uint32_t>(p), make_stencil<D, K>(P.x[p], g.origin, inv_h, a, &g.clamped));
  });
  scatter_strays([&](std::uint32_t p) { scatter_one(p, make_stencil<D, K>(P.x[p], g.origin, inv_h, a, &g.clamped)); });
}

template <int D>
void Solver<D>::p2g(bool with_forces) {
  const auto timer = clock_.scope(Stage::p2g);
  with_kernel(sc_.settings.kernel, [&](auto K) { this->template p2g_impl<decltype(K)::value>(true, with_forces); });
}

template <int D>
void Solver<D>::p2g_forces() {
  const auto timer = clock_.scope(Stage::p2g);
  with_kernel(sc_.settings.kernel, [&](auto K) { this->template p2g_impl<decltype(K)::value>(false, true); });
}

template <int D>
template <Kernel K>
void Solver<D>::rigid_p2g_impl() {
  presence_.template scatter<K>(sc_.grid, sc_.bodies, HalfWidth(half_width_), steps_, t_);
  mark_offset_bases<K>();
}

template <int D>
template <Kernel K>
void Solver<D>::mark_offset_bases() {
  const bool usl = sc_.settings.integrator == Integrator::usl;
  masks_.template mark_offsets<K>(sc_.grid, sc_.bodies, presence_, HalfWidth(half_width_), t_, dt_, usl);
}

template <int D>
void Solver<D>::mark_contact_bases() {
  const bool usl = sc_.settings.integrator == Integrator::usl;
  const bool field_contact = usl && sc_.contact.fields >= 2 && !sc_.contact.all_weld();
  masks_.mark_contact(sc_.grid, sc_.deformable_fields, field_contact, exchange_ ? exchange_->first_line() : 0,
                      exchange_ ? exchange_->last_line() : std::numeric_limits<long>::max());
}

template <int D>
void Solver<D>::rigid_p2g() {
  const auto timer = clock_.scope(Stage::rigid_p2g);
  with_kernel(sc_.settings.kernel, [&](auto K) { this->template rigid_p2g_impl<decltype(K)::value>(); });
}

template <int D>
void Solver<D>::contact(bool record, bool after_update) {
  const auto timer = clock_.scope(Stage::contact);
  // After the grid update the rigid bodies act last, so that the walls' constraint holds at the
  // end of the step. The other order (walls, then the fields' exchange) let a field at a wall node
  // leave the exchange moving into the wall, which the wall met only at the next step: where two
  // grain fields meet a wall at 20 um cells the particles there were squeezed a little more every
  // step, an instability that grew at the decks' cfl = 0.4 (von Mises doubling every 0.03 % of
  // strain to GPa, kinetic energy plus stress work 2-6x the punch work by 0.3 % strain, seeds 1
  // and 2; cfl 0.2 hid it; 2026-12-05, docs/theory/paper_study.md "Energy"), and a binder_layer
  // spring could push a grain into the wall the same way (KE/IE 0.001 -> 0.07 over 80 steps). The
  // pass before the update keeps the order walls -> fields (the walls last there changed nothing
  // measurable).
  const bool walls_last = after_update;
  if (!walls_last) rigid_stage(record);
  if (sc_.contact.fields < 2 || sc_.contact.all_weld()) {
    weld_fields<D>(sc_.grid, sc_.deformable_fields, mass_eps_);
  } else {
    if (after_update && sc_.contact.has_layers()) sc_.contact.layers_at(t_ + dt_);
    const bool smooth = sc_.contact.springs_through_particles && after_update && sc_.contact.has_layers();
    if (smooth) springs_.size_for(static_cast<long>(sc_.deformable_fields) * sc_.grid.nodes(), sc_.grid.nodes());
    std::function<void(double)> book_friction;
    if (record) book_friction = [this](double w) { dissipated_ += w, friction_ += w; };
    field_contact<D>(sc_.grid, sc_.contact, sc_.deformable_fields, dt_, mass_eps_, record ? &contact_tally_ : nullptr,
                     after_update, after_update ? &layer_energy_ : nullptr,
                     sc_.layer_data.on() ? &sc_.layer_data.sums : nullptr, smooth ? &springs_ : nullptr, &bins_,
                     book_friction);
    if (smooth) spring_impulses_through_particles();
    if (after_update && !sc_.layer_data.bonds.empty()) bond_impulses();
  }
  if (walls_last) rigid_stage(record);
}

// USF and MUSL take the velocity gradient L from other nodal velocities than those that move the
// particles: USF from the next step's interpolated momenta after the contact pass that follows
// P2G, MUSL from the updated particle momenta mapped back to the grid after a contact pass of their
// own. In the bulk the two agree to O(dt); at a contact node they need not: the particles there
// moved with the velocity this final pass set (a stuck field at the wall's velocity, a pressed one
// with no normal approach), while the interpolated or remapped momenta carry the particle
// velocities, which near the interface hold the interior's motion, and a second pass of the law
// cannot restore the constraint: without the step's forces its Coulomb cap (mu times the
// interpolated approach) is nearly zero on a resting contact. L then saw a stuck field slip and a
// pressed one separate, and the stress a deformation the particles never made: on the inclined
// plane (20 deg, mu 0.5) a grid-scale vibration grew to 0.07 m/s rms and the block crept at
// 0.07 m/s, 2.9-3.0 % of a frictionless slide in 10 us (USL: 0.13-0.20 %). Where this pass changed a
// field's momentum L therefore takes the final velocity (as USL does everywhere): MUSL within the
// step, USF at the next step, whose L stands for its start (0.18-0.27 %; docs/theory/engine.md,
// "Contact nodes in USF and MUSL").
template <int D>
void Solver<D>::final_contact() {
  auto& g = sc_.grid;
  const long nd = static_cast<long>(sc_.deformable_fields) * g.nodes();
  // the momenta before the pass, in vel (free until finalize_grid_velocities; contact reads only
  // mass, momentum and the sums P2G made)
#pragma omp parallel for schedule(static)
  for (long k = 0; k < nd; ++k) g.vel[k] = g.mom[k];
  contact(true, true);
  contact_vel_.clear();
  for (long k = 0; k < nd; ++k)
    if (g.mass[k] > mass_eps_ && g.mom[k] != g.vel[k]) contact_vel_.emplace_back(k, Vec<D>::Zero());
}

// After finalize_grid_velocities: the final velocities of the node-fields final_contact listed.
template <int D>
void Solver<D>::keep_contact_velocities() {
  for (auto& [k, v] : contact_vel_) v = sc_.grid.vel[k];
}

// A spring reads its jump from the particle sums of its two sides at the node, u_f(i) = sum_p
// m_p S_ip u_p / m_f(i): a weighted mean A u of the displacements the nodes around it give those
// particles. The force whose work is the change of its energy 1/2 k |A u|^2 is A^T k A u, so an
// impulse J applied at the node alone (k A u) is a non-symmetric stiffness, which can feed a mode.
// Handed back through the same weights instead, each particle of field f takes
// dp_p = m_p sum_i S_ip J_f(i) / m_f(i), and the nodes receive sum_p S_jp dp_p: A^T J, the same
// total impulse per field (sum_j S_jp = 1 and sum_p m_p S_ip = m_f(i)). In the scatter's parity
// phases (thread-count independent).
template <int D>
void Solver<D>::spring_impulses_through_particles() {
  with_kernel(sc_.settings.kernel, [&](auto K) { this->template spring_impulses_impl<decltype(K)::value>(); });
}

template <int D>
template <Kernel K>
void Solver<D>::spring_impulses_impl() {
  auto& g = sc_.grid;
  const auto& P = sc_.particles;
  const double inv_h = 1.0 / g.h, fs = sc_.settings.mass_scaling;
  const HalfWidth a(half_width_);
  const long nn = g.nodes();
  const std::vector<std::uint8_t>& spring_node = springs_.node;  // flagged by field_contact
  const std::vector<Vec<D>>& imp = springs_.impulse;
  const bool springs = std::find(spring_node.begin(), spring_node.end(), std::uint8_t{1}) != spring_node.end();
  // a decomposed run's ranks take the pass together (its exchange), if a spring acts on any of them
  if (!(exchange_ ? exchange_->max(springs ? 1.0 : 0.0) > 0.0 : springs)) return;
  auto hand = [&](std::size_t p) {
    const Stencil<D> st = make_stencil<D, K>(P.x[p], g.origin, inv_h, a, &g.clamped);
    const long off = static_cast<long>(P.field[p]) * nn;
    Vec<D> take = Vec<D>::Zero();
    bool any = false;
    for_each_node<D>(st, g.stride, [&](long i, double S, const Vec<D>&) {
      if (!spring_node[static_cast<std::size_t>(i)]) return;
      const long k = off + i;
      const Vec<D>& J = imp[static_cast<std::size_t>(k)];
      if (J == Vec<D>::Zero() || !(g.mass[k] > 0.0)) return;
      take += (S / g.mass[k]) * J;
      any = true;
    });
    if (!any) return;
    const Vec<D> dp = (P.mass[p] * fs) * take;
    for_each_node<D>(st, g.stride, [&](long i, double S, const Vec<D>&) { g.mom[off + i] += S * dp; });
  };
  // The scatter's parity phases and serial strays (grid/strip_bins.hpp): race-free, and the sum
  // order at every node fixed by storage order and positions, whatever the thread count.
  scatter_home([&](long p) { hand(static_cast<std::size_t>(p)); });
  scatter_strays(hand);
  // leave the buffers zero for the next pass (only the flagged nodes were written)
  const long nf = sc_.deformable_fields;
  for (long i = 0; i < nn; ++i) {
    if (!springs_.node[static_cast<std::size_t>(i)]) continue;
    springs_.node[static_cast<std::size_t>(i)] = 0;
    for (long f = 0; f < nf; ++f) springs_.impulse[static_cast<std::size_t>(f * nn + i)] = Vec<D>::Zero();
  }
}

// film = "bonds": every pair's spring acts over the step with the force at the particles' positions
// at its start (explicit; uncapped the gradient of one energy, so the pairs make none; stable below
// bond_dt_; the shear cap as at a node, bond_force).
// Each particle's impulse reaches its field's nodes by its shape functions, as its momentum does in
// P2G; the pairs' energy at the start of the step (bond_force) is booked as the layers' energy.
template <int D>
void Solver<D>::bond_impulses() {
  with_kernel(sc_.settings.kernel, [&](auto K) { this->template bond_impulses_impl<decltype(K)::value>(); });
}

template <int D>
template <Kernel K>
void Solver<D>::bond_impulses_impl() {
  auto& g = sc_.grid;
  const auto& P = sc_.particles;
  const long nn = g.nodes();
  double energy = 0;
  for (const auto& b : sc_.layer_data.bonds) {
    const LayerLaw& L = sc_.contact.layers[static_cast<std::size_t>(b.layer)];
    const BondForce<D> F = bond_force<D>(L, b.coef, b.n0, Vec<D>((P.x[b.q] - P.x[b.p]) - b.d0));
    const Vec<D> J = dt_ * F.f;
    bond_dp_[b.p] += J;
    bond_dp_[b.q] -= J;
    energy += F.energy;
  }
  layer_energy_ += energy;
  const double inv_h = 1.0 / g.h;
  const HalfWidth a(half_width_);
  auto hand = [&](std::size_t p) {
    const Vec<D>& dp = bond_dp_[p];
    if (dp == Vec<D>::Zero()) return;
    const Stencil<D> st = make_stencil<D, K>(P.x[p], g.origin, inv_h, a, &g.clamped);
    const long off = static_cast<long>(P.field[p]) * nn;
    for_each_node<D>(st, g.stride, [&](long i, double S, const Vec<D>&) { g.mom[off + i] += S * dp; });
  };
  scatter_home([&](long p) { hand(static_cast<std::size_t>(p)); });
  scatter_strays(hand);
  for (const auto& b : sc_.layer_data.bonds) bond_dp_[b.p] = bond_dp_[b.q] = Vec<D>::Zero();
}

template <int D>
void Solver<D>::rigid_stage(bool record) {
  if (!sc_.bodies.empty()) {
    std::function<void(const RigidContactResult<D>&)> book;
    if (record)
      book = [this](const RigidContactResult<D>& r) {
        for (std::size_t b = 0; b < sc_.bodies.size(); ++b) {
          sc_.bodies[b].impulse += r.impulse[b];
          sc_.bodies[b].work += r.work[b];
          dissipated_ += r.friction_work[b];
          friction_ += r.friction_work[b];
        }
      };
    // The bodies' velocity over the step (t_n+1): also in MUSL's unrecorded remap pass, whose
    // momenta carry the end-of-step velocities (it used t_n: a punch lag of up to 1e-4 m/s in the ramp).
    rigid_contact<D>(sc_.grid, sc_.bodies, sc_.deformable_fields, t_ + dt_, mass_eps_, presence_.nodes(), book, &bins_);
  }
}

template <int D>
void Solver<D>::grid_update() {
  const auto timer = clock_.scope(Stage::grid_update);
  auto& g = sc_.grid;
  const double dt = dt_, eps = mass_eps_;
  const double* mass = g.mass.data();
  const Vec<D>* force = g.force.data();
  Vec<D>* mom = g.mom.data();
  for_each_visited_run([&](long b, long e) {
    for (long k = b; k < e; ++k)
      if (mass[k] > eps) mom[k] += dt * force[k];
  });
}

template <int D>
void Solver<D>::finalize_grid_velocities() {
  const auto timer = clock_.scope(Stage::grid_update);
  auto& g = sc_.grid;
  const double eps = mass_eps_;
  const double* mass = g.mass.data();
  const Vec<D>*mom = g.mom.data(), *mom0 = g.mom0.data();
  Vec<D>*vel = g.vel.data(), *dvel = g.dvel.data();
  for_each_visited_run([&](long b, long e) {
    for (long k = b; k < e; ++k) {
      if (mass[k] > eps) {
        const double inv_m = 1.0 / mass[k];
        vel[k] = mom[k] * inv_m;
        dvel[k] = (mom[k] - mom0[k]) * inv_m;
      } else {
        vel[k].setZero();
        dvel[k].setZero();
      }
    }
  });
}

// G2P: particle velocity by the FLIP/PIC blend, and per integrator:
//   USF: position update;  USL: position update and L from the updated nodal velocities (the
//   USL step uses the fused pass g2p_update_p2g instead);
//   MUSL: scatter of the updated particle momentum (positions move after the remap).
template <int D>
template <Kernel K>
void Solver<D>::g2p_impl() {
  auto& g = sc_.grid;
  auto& P = sc_.particles;
  const double inv_h = 1.0 / g.h, dt = dt_, alpha = sc_.settings.flip;
  const HalfWidth a(half_width_);
  const long nn = g.nodes();
  const Integrator integ = sc_.settings.integrator;
  const bool musl = integ == Integrator::musl, usl = integ == Integrator::usl;
  if (musl) {
    const long n = static_cast<long>(sc_.deformable_fields) * nn;
#pragma omp parallel for schedule(static)
    for (long k = 0; k < n; ++k) g.mom[k].setZero();
  }
  // MUSL maps the new momenta back: momentum only, from the start-of-step positions
  const Scatter<D> remap = scatter(true, false);
  auto scatter_momentum = [&](std::uint32_t p, const Stencil<D>& st) {
    const Vec<D> mv = (P.mass[p] * remap.fs) * P.v[p];
    Vec<D>* gp = g.mom.data() + P.field[p] * nn;
    for_each_node<D>(st, g.stride, [&](long i, double S, const Vec<D>&) { gp[i] += S * mv; });
  };
  double vmax2 = 0;
  std::uint32_t bad = kNone, left = kNone;
  long strays = 0;
  for (int phase = 0; phase < 2; ++phase) {
#pragma omp parallel for schedule(dynamic, 1) reduction(max : vmax2) reduction(min : bad, left) reduction(+ : strays)
    for (long k = 0; k < bins_.phase_size(phase); ++k) {
      const long s = bins_.phase_strip(phase, k);
      for (long q = bins_.begin[static_cast<std::size_t>(s)]; q < bins_.begin[static_cast<std::size_t>(s + 1)]; ++q) {
        const auto p = static_cast<std::uint32_t>(q);
        const Stencil<D> st = make_stencil<D, K>(P.x[p], g.origin, inv_h, a, &g.clamped);
        const Gathered<D> r = gather<D>(g, P.field[p] * nn, st, usl);
        const Vec<D> vnew = alpha * (P.v[p] + r.dv) + (1.0 - alpha) * r.vpic;
        P.v[p] = vnew;
        if (musl) {
          if (!bins_.stray[p]) scatter_momentum(p, st);
        } else {
          P.x[p] += dt * r.vpic;
          if (usl) P.L[p] = r.L;
          bins_.relocate<D>(g, inv_h, P.x[p], s, p, left, strays);
        }
        const double sp2 = vnew.squaredNorm();  // sqrt once, of the maximum (monotonic)
        if (!(sp2 < 1e300)) bad = std::min(bad, p);
        vmax2 = std::max(vmax2, sp2);
      }
    }
  }
  if (musl) {
    for (const std::uint32_t p : bins_.strays)
      scatter_momentum(p, make_stencil<D, K>(P.x[p], g.origin, inv_h, a, &g.clamped));
  } else {
    left_grid_ = left;
    bins_.collect_strays(strays);
  }
  vmax_ = std::sqrt(vmax2);
  if (bad != kNone)
    throw InstabilityError(fmt::format("step {}: particle {} (material '{}') has a non-finite velocity", steps_, bad,
                                       sc_.material_names[P.material[bad]]));
}

template <int D>
void Solver<D>::g2p() {
  const auto timer = clock_.scope(Stage::g2p);
  with_kernel(sc_.settings.kernel, [&](auto K) { this->template g2p_impl<decltype(K)::value>(); });
}

// MUSL: L from the remapped nodal velocities, then the position update with the step's velocities,
// both with the shape functions of the start of the step.
template <int D>
template <Kernel K>
void Solver<D>::remap_gradient_impl() {
  auto& g = sc_.grid;
  auto& P = sc_.particles;
  const double inv_h = 1.0 / g.h, dt = dt_;
  const HalfWidth a(half_width_);
  const long nn = g.nodes();
  const long nd = static_cast<long>(sc_.deformable_fields) * nn;
#pragma omp parallel for schedule(static)
  for (long k = 0; k < nd; ++k) g.dvel[k] = g.mass[k] > mass_eps_ ? Vec<D>(g.mom[k] / g.mass[k]) : Vec<D>::Zero();
  // strip by strip (a gather: no parity phases), so that the end-of-step check knows each
  // particle's home strip
  std::uint32_t left = kNone;
  long strays = 0;
#pragma omp parallel for schedule(dynamic, 1) reduction(min : left) reduction(+ : strays)
  for (long s = 0; s < bins_.strips; ++s) {
    for (long q = bins_.begin[static_cast<std::size_t>(s)]; q < bins_.begin[static_cast<std::size_t>(s + 1)]; ++q) {
      const auto p = static_cast<std::uint32_t>(q);
      const Stencil<D> st = make_stencil<D, K>(P.x[p], g.origin, inv_h, a, &g.clamped);
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
      bins_.relocate<D>(g, inv_h, P.x[p], s, p, left, strays);
    }
  }
  left_grid_ = left;
  bins_.collect_strays(strays);
}

template <int D>
void Solver<D>::remap_velocity_gradient() {
  const auto timer = clock_.scope(Stage::g2p);
  with_kernel(sc_.settings.kernel, [&](auto K) { this->template remap_gradient_impl<decltype(K)::value>(); });
}

template <int D>
template <Kernel K>
void Solver<D>::velocity_gradient_impl() {
  auto& g = sc_.grid;
  auto& P = sc_.particles;
  const double inv_h = 1.0 / g.h;
  const HalfWidth a(half_width_);
  const long nn = g.nodes();
  const long nd = static_cast<long>(sc_.deformable_fields) * nn;
#pragma omp parallel for schedule(static)
  for (long k = 0; k < nd; ++k) g.vel[k] = g.mass[k] > mass_eps_ ? Vec<D>(g.mom[k] / g.mass[k]) : Vec<D>::Zero();
  // where the last step's final contact pass acted: its velocity (final_contact)
  for (const auto& [k, v] : contact_vel_)
    if (g.mass[k] > mass_eps_) g.vel[k] = v;
  const long np = static_cast<long>(P.size());
#pragma omp parallel for schedule(static)
  for (long p = 0; p < np; ++p) {
    const Stencil<D> st = make_stencil<D, K>(P.x[p], g.origin, inv_h, a, &g.clamped);
    const Vec<D>* gv = g.vel.data() + P.field[p] * nn;
    Mat<D> L = Mat<D>::Zero();
    for_each_node<D>(st, g.stride, [&](long i, double, const Vec<D>& G) { L += gv[i] * G.transpose(); });
    P.L[p] = L;
  }
}

template <int D>
void Solver<D>::velocity_gradient() {
  const auto timer = clock_.scope(Stage::g2p);
  with_kernel(sc_.settings.kernel, [&](auto K) { this->template velocity_gradient_impl<decltype(K)::value>(); });
}

// Kinematics (F, J, V) and the material laws, one call per material per chunk of its batch.
template <int D>
void Solver<D>::update_stress() {
  const auto timer = clock_.scope(Stage::stress);
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
        P.F[p] = advance_deformation_gradient<D>(P.F[p], P.L[p], dt);
        const double J = P.F[p].determinant();
        if (!(J > 0)) worst = std::min(worst, p);
        P.volume[p] = J * P.volume0[p];
      }
      if (worst == kNone) {
        const MaterialBatch<D> batch = material_batch<D>(P, st, hs, b, e - b, dt);
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
      if (p != kNone) stop_on_bad_stress(p);
      const auto& r = res[static_cast<std::size_t>(c)];
      internal_ += r.stress_work;
      dissipated_ += r.dissipated;
      dissipated_material_[m] += r.dissipated;
      cmax = std::max(cmax, r.max_wave_speed);
    }
  }
  cmax_ = cmax;
}

template <int D>
void Solver<D>::advance_bodies() {
  const auto timer = clock_.scope(Stage::bodies);
  for (auto& b : sc_.bodies)
    if (b.moving()) b.move_to(t_);
  // The positions were checked where they were updated (G2P, the fused pass or the MUSL remap).
  if (left_grid_ != kNone) stop_on_left_grid(left_grid_);
}

template <int D>
void Solver<D>::stop_on_left_grid(std::uint32_t p) const {
  const auto& P = sc_.particles;
  throw InstabilityError(
      fmt::format("step {} (t = {:.6g} s): particle {} of material '{}' left the grid at ({:.6g}, {:.6g}) m", steps_,
                  t_, p, sc_.material_names[P.material[p]], P.x[p][0], P.x[p][1]));
}

template <int D>
double Solver<D>::kinetic_energy() const {
  const auto& P = sc_.particles;
  const double fs = sc_.settings.mass_scaling;
  return bins_.fold(0.0, [&](long s, double& e) {
    for (long p = bins_.begin[static_cast<std::size_t>(s)]; p < bins_.begin[static_cast<std::size_t>(s + 1)]; ++p)
      e += 0.5 * fs * P.mass[p] * P.v[p].squaredNorm();
  });
}

template <int D>
void Solver<D>::stop_on_bad_stress(std::uint32_t p) const {
  const auto& P = sc_.particles;
  const double J = P.F[p].determinant();
  std::string what = fmt::format("J = {:.4g} <= 0 (inverted)", J);
  if (J > 0) {
    const std::string why = sc_.materials[P.material[p]]->failure_reason(J);
    what = fmt::format("a non-finite stress at J = {:.4g}{}{}", J, why.empty() ? "" : ": ", why);
  }
  // the step's scale beside it: a particle or body that crossed much of a cell in one step is
  // the usual cause (a too-fast punch, a mass scaling too large for the loading)
  double body_speed = 0;
  for (const auto& b : sc_.bodies) body_speed = std::max(body_speed, b.velocity.norm());
  throw InstabilityError(fmt::format(
      "step {} (t = {:.6g} s, dt = {:.4g} s): particle {} of material '{}' at ({:.6g}, {:.6g}) m has {}; in this "
      "step the fastest particle moved {:.3g} cells, the fastest rigid body {:.3g} cells (mass scaling {:g})",
      steps_, t_, dt_, p, sc_.material_names[P.material[p]], P.x[p][0], P.x[p][1], what, vmax_ * dt_ / sc_.grid.h,
      body_speed * dt_ / sc_.grid.h, sc_.settings.mass_scaling));
}

template class Solver<2>;
template class Solver<3>;

}  // namespace pbx
