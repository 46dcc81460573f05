#pragma once
#include <cstdint>
#include <functional>
// Contact between deformable velocity fields at shared nodes (the paper's Eq. 6-7 in Nairn's
// momentum form of Bardenhagen et al. 2000/2001). docs/theory/contact.md states the law exactly as
// implemented; in short, at a node where field a meets the rest r of the fields:
//   stick impulse      dp = (m_a p_r - m_r p_a) / (m_a + m_r)
//   contact            when d_n = dp . n_a < 0 (approaching), and, with the displacement check on,
//                      when the mass centres of a and r are closer than the cutoff along n_a
//   impulse on a       d_n n_a + dp_t min(1, (S_a A_c dt - mu d_n) / |dp_t|)   (weld: dp)
//   binder_layer       where both sides are bonded: the implicit impulse of a spring on the
//                      displacement jump, J = dt k s / (1 + k dt^2 / m_red) per direction
// and the node's impulses are made to sum to zero exactly (mass-weighted correction, which only
// acts at nodes with three or more fields or with unpaired normals).
#include "contact/contact_matrix.hpp"
#include "contact/contact_tally.hpp"
#include "contact/layer_data.hpp"
#include "grid/grid.hpp"
#include "grid/strip_bins.hpp"

namespace pbx {

// Single-velocity limit: every field at a node moves with the node's centre-of-mass velocity.
template <int D>
void weld_fields(Grid<D>& grid, int deformable, double mass_eps);

// Applies the contact matrix to the momenta of fields [0, deformable) at every node with at least
// two fields; dt is the step (adhesion cap). Returns the frictional work of the pass, J
// (per metre of depth in 2-D), summed in a thread-count independent order. With a tally, the
// impulses of the pass are added to it per pair of fields (history bookkeeping).
// binder_layer pairs (contact/binder_layer.hpp) act only in the pass after the grid update
// (after_update), where the impulse of their springs is applied; with layer_energy, the energy the
// springs hold at the end of the step is written there, J (per metre of depth in 2-D). Their springs
// read the layer sums of the step's P2G (layer_sums: required when the matrix has binder_layer pairs,
// a std::logic_error otherwise).
// With spring_impulses, the impulses of every node where a binder-layer spring acted go there
// instead of into the momenta, and the node is flagged: the caller hands them through the particles
// that define the springs' jumps (Solver::spring_impulses_through_particles).
// The sums (work, energy, tally) are taken strip by strip over `strips` (grid/strip_bins.hpp; null:
// the grid's strips, all this process's), in a decomposed run over its ranks. With book_work, the
// work is also handed to it. Where `strips` defer their sums (a decomposed run's books,
// StripBins::fold_then), the tally, the layer energy and book_work receive them at the next
// settle, and the return value is NaN: the work is known only through book_work.
template <int D>
struct SpringImpulses {
  std::vector<Vec<D>> impulse;     // per node-field; zero on entry
  std::vector<std::uint8_t> node;  // per node: 1 where a spring acted; zero on entry
  // sized for the grid, all zero (the caller keeps them zero between passes)
  void size_for(long node_fields, long nodes) {
    if (static_cast<long>(impulse.size()) != node_fields)
      impulse.assign(static_cast<std::size_t>(node_fields), Vec<D>::Zero());
    if (static_cast<long>(node.size()) != nodes) node.assign(static_cast<std::size_t>(nodes), 0);
  }
};

template <int D>
double field_contact(Grid<D>& grid, const ContactMatrix& cm, int deformable, double dt, double mass_eps,
                     ContactTally<D>* tally = nullptr, bool after_update = false, double* layer_energy = nullptr,
                     const LayerSums<D>* layer_sums = nullptr, SpringImpulses<D>* springs = nullptr,
                     const StripBins* strips = nullptr, const std::function<void(double)>& book_work = {});

}  // namespace pbx
