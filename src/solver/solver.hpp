#pragma once
// The explicit MPM time step. step() reads like the algorithm of the paper (Eq. 1-5):
//   P2G -> contact -> grid update -> contact -> G2P -> stress update
// with the integrator (USF / USL / MUSL) deciding where the velocity gradient is taken.
// Each stage is a member function that can be tested alone. The default USL step runs G2P, the
// stress update and the next step's P2G as one fused particle pass (g2p_update_p2g, in
// solver/particle_pass.cpp), which calls the same per-particle kernels as the separate stages.
#include <cstdint>
#include <limits>
#include <stdexcept>
#include <utility>
#include <vector>

#include "bodies/body_presence.hpp"
#include "contact/contact_tally.hpp"
#include "contact/field_contact.hpp"
#include "contact/scatter_masks.hpp"
#include "grid/strip_bins.hpp"
#include "solver/scatter_exchange.hpp"
#include "solver/scene.hpp"
#include "solver/stage_clock.hpp"
#include "solver/transfer.hpp"

namespace pbx {

template <int D>
class Solver {
 public:
  explicit Solver(Scene<D>& scene);

  // One step of the stable size, or of max_dt if that is shorter (the last step of a run lands
  // exactly on its end time).
  void step(double max_dt = std::numeric_limits<double>::infinity());

  double time() const { return t_; }
  double dt() const { return dt_; }
  long step_count() const { return steps_; }
  Scene<D>& scene() { return sc_; }
  const Scene<D>& scene() const { return sc_; }

  // The run's books (the energies below, the bodies' impulses and work, the contact tally) are
  // complete only after settle_books(): a decomposed run's ranks gather the step's sums for them
  // once per history row (core/parallel.hpp, DeferredSums). Collective there: every rank calls
  // it at the same step. One process books every sum at once. The getters of the books refuse to
  // read them while sums wait (a std::logic_error).
  void settle_books() { books_.settle(); }

  // Energies of the deformable particles, J (per metre of depth in 2D).
  double kinetic_energy() const;  // with the scaled (inertial) masses
  // integrated stress work, plus the energy held by binder-layer springs (field contact)
  double internal_energy() const { return settled(internal_ + layer_energy_); }
  // the part of it the binder-layer springs hold at the end of the last step
  double layer_energy() const { return settled(layer_energy_); }
  double dissipated_energy() const { return settled(dissipated_); }  // plastic/viscous + friction
  // its parts: each material's plastic and viscous work (sc.materials order), and the friction work
  // of the field contact and the rigid bodies, J (per metre of depth in 2D)
  const std::vector<double>& dissipated_by_material() const { return settled(dissipated_material_); }
  double friction_work() const { return settled(friction_); }
  long stray_count() const { return static_cast<long>(bins_.strays.size()); }  // particles outside their home strip
  double max_wave_speed() const { return cmax_; }                              // unscaled, m/s
  // Impulses exchanged between deformable fields since the last clear (history bookkeeping).
  ContactTally<D>& contact_tally() { return settled(contact_tally_); }
  // Wall seconds per stage since construction or the last clear (solver/stage_clock.hpp).
  StageClock& stage_clock() { return clock_; }
  const StageClock& stage_clock() const { return clock_; }

  // Clock and accumulators, saved in checkpoints and restored on restart.
  struct State {
    double t, dt, cmax, vmax, internal, dissipated;
    long steps;
    std::vector<double> dissipated_by_material;  // empty: not known (a checkpoint written before 2026-12-06)
    double friction = 0;
  };
  State state() const {
    return {t_, dt_, cmax_, vmax_, settled(internal_), dissipated_, steps_, dissipated_material_, friction_};
  }
  void restore(const State& s);  // also moves the rigid bodies and re-locates the particles
  // USF: the node-fields the last step's final contact pass acted on (grid.at(field, node)) and
  // their final velocities, which the next step's velocity gradient takes there (final_contact in
  // solver.cpp); part of a USF run's state, saved in its checkpoints. Empty for USL, and for MUSL
  // between steps.
  using ContactVelocities = std::vector<std::pair<long, Vec<D>>>;
  const ContactVelocities& contact_velocities() const { return contact_vel_; }
  void restore_contact_velocities(ContactVelocities cv) { contact_vel_ = std::move(cv); }

  // Stages (public so tests can drive them one by one).
  double stable_time_step() const;
  void reset_grid();
  void p2g(bool with_forces);
  void p2g_forces();
  void rigid_p2g();
  // record: book impulses and friction work; after_update: the pass after the grid update
  // (binder-layer springs act only there).
  void contact(bool record, bool after_update = false);
  void grid_update();
  void keep_interpolated_momentum();
  void finalize_grid_velocities();
  void g2p();
  void remap_velocity_gradient();
  void update_stress();
  // USL: G2P, stress update and the next step's P2G, chunk by chunk of each strip's particles.
  void g2p_update_p2g();
  void advance_bodies();

  static constexpr std::uint32_t kNone = std::numeric_limits<std::uint32_t>::max();

  // A decomposed run (issue 28; docs/architecture.md, "One run over many ranks", for what is built):
  // the exchange that completes the nodal sums of the shared node lines between the scatter's
  // parity phases, and the mass threshold of the whole scene (a sum over every particle, which no
  // rank holds). Also takes the ranks' largest particle speed, which the first step's size reads.
  void set_scatter_exchange(ScatterExchange* exchange, double mass_threshold);
  double mass_threshold() const { return mass_eps_; }
  // The strips (where each begins in storage order, their width), for a partition over ranks.
  const StripBins& strips() const { return bins_; }

 private:
  // The rigid bodies' part of the contact stage (src/contact/rigid_contact.hpp), recorded in the
  // bodies' impulses and work when `record`.
  void rigid_stage(bool record);
  // The binder-layer springs' impulses of a contact pass (springs_), handed to the momenta
  // through the particles whose sums define the springs' jumps (see solver.cpp).
  void spring_impulses_through_particles();
  template <Kernel K>
  void spring_impulses_impl();
  // film = "bonds": the particle pairs' spring impulses over the step, handed to the grid through
  // the particles' shape functions (see solver.cpp)
  void bond_impulses();
  template <Kernel K>
  void bond_impulses_impl();
  // Stops the run on particle p, whose stress update gave J <= 0 or a non-finite stress: the
  // message names the step, the particle, its material and place, and the material's reason.
  [[noreturn]] void stop_on_bad_stress(std::uint32_t p) const;
  [[noreturn]] void stop_on_left_grid(std::uint32_t p) const;
  // particles per chunk of the fused pass: G2P, stress update and P2G of one chunk run while
  // its particle data are still in the L1/L2 cache
  static constexpr long kPassChunk = 256;
  template <Kernel K>
  void p2g_impl(bool mass_momentum, bool forces);
  template <Kernel K>
  void g2p_impl();
  template <Kernel K>
  void remap_gradient_impl();
  template <Kernel K>
  void velocity_gradient_impl();
  template <Kernel K>
  void rigid_p2g_impl();
  template <Kernel K>
  void mark_offset_bases();
  void mark_contact_bases();
  template <Kernel K>
  void particle_pass_impl();
  void velocity_gradient();  // USF: L from the interpolated velocities
  // USF and MUSL: the contact pass after the grid update, which also lists the node-fields it
  // changed (contact_vel_), and, after finalize_grid_velocities, their final velocities.
  void final_contact();
  void keep_contact_velocities();
  Scatter<D> scatter(bool mass_momentum, bool forces);
  void setup_strips();
  // f(p) for every home particle, in the scatter's parity phases (solver.cpp)
  template <class F>
  void scatter_home(F&& f);
  // f(begin, end) over the node-fields of the deformable fields this process's node stages visit
  // (solver.cpp)
  template <class F>
  void for_each_visited_run(F&& f);
  // The strays' serial scatter, hand(p) per stray in index order; in a decomposed run every rank
  // takes it with the stray zones' exchange when any rank has a stray.
  // anywhere: whether any rank has a stray, when the caller has asked the ranks already (-1: ask)
  template <class F>
  void scatter_strays(F&& hand, int anywhere = -1) {
    if (exchange_) {
      if (anywhere < 0) anywhere = exchange_->max(bins_.strays.empty() ? 0.0 : 1.0) > 0.0;
      if (!anywhere) return;
      const auto [lo, hi] = refuse_far_strays();
      exchange_->before_strays(lo, hi);
      for (const std::uint32_t p : bins_.strays) hand(p);
      exchange_->after_strays();
      return;
    }
    for (const std::uint32_t p : bins_.strays) hand(p);
  }
  // stops every rank if a stray is further than one strip from home; the node lines the strays reach
  std::pair<long, long> refuse_far_strays();
  void locate_particles();
  // x, after checking that no sum of the books waits for a settle
  template <class T>
  const T& settled(const T& x) const {
    if (books_.pending())
      throw std::logic_error("Solver: the run's books were read before settle_books() (a decomposed run's sums wait)");
    return x;
  }
  template <class T>
  T& settled(T& x) {
    std::as_const(*this).settled(std::as_const(x));
    return x;
  }

  Scene<D>& sc_;
  StripBins bins_;
  double t_ = 0, dt_ = 0;
  long steps_ = 0;
  double cmax_ = 0, vmax_ = 0;
  double internal_ = 0, dissipated_ = 0;
  std::vector<double> dissipated_material_;  // the parts of dissipated_ (dissipated_by_material())
  double friction_ = 0;
  double layer_energy_ = 0;  // binder-layer springs at the end of the last step (a state, not a sum)
  double mass_eps_ = 0;
  double half_width_ = 0;         // particle half-width in cells (uGIMP)
  bool track_gradients_ = false;  // volume gradients for contact normals (several fields)
  // end-of-step check, filled where the positions are updated (G2P, fused pass or MUSL remap)
  std::uint32_t left_grid_ = kNone;             // lowest particle whose stencil left the grid
  bool grid_primed_ = false;                    // the last fused pass made this step's P2G
  std::vector<std::vector<long>> batch_begin_;  // [material][strip]: first batch position
  std::vector<long> chunk_begin_;               // [strip]: first fused-pass chunk (results order)
  BodyPresence<D> presence_;                    // the rigid bodies on the grid (rigid_p2g)
  // which particles' next P2G must scatter the contact stages' data (mark_offset_bases,
  // mark_contact_bases)
  ContactScatterMasks<D> masks_;
  ContactTally<D> contact_tally_;
  StageClock clock_;
  // USF and MUSL (final_contact): the node-fields the final contact pass changed, ascending, with
  // their final velocities
  ContactVelocities contact_vel_;
  SpringImpulses<D> springs_;    // the springs' impulses of the pass after the update, and their nodes
  std::vector<Vec<D>> bond_dp_;  // film = "bonds": each particle's impulse from its pairs this step
  double bond_dt_ = std::numeric_limits<double>::infinity();  // the pairs' stable step (their stiffest mode)
  ScatterExchange* exchange_ = nullptr;                       // a decomposed run's halo exchange (null: one process)
  DeferredSums books_;  // where the books' sums wait in a decomposed run (bins_.deferred)
};

}  // namespace pbx
