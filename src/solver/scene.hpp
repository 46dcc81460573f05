#pragma once
// A Scene is everything a run needs (setup/build_scene.hpp builds one from a deck): grid, particles, materials with
// their batches and history, rigid bodies (die walls and punch), solver settings, run control.
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "bodies/die.hpp"
#include "bodies/rigid_body.hpp"
#include "contact/contact_matrix.hpp"
#include "contact/layer_data.hpp"
#include "grid/grid.hpp"
#include "grid/shape.hpp"
#include "materials/material.hpp"
#include "microstructure/packing.hpp"
#include "particles/particles.hpp"

namespace pbx {

enum class Integrator { usf, usl, musl };

template <int D>
struct SolverSettings {
  Kernel kernel = Kernel::ugimp;
  Integrator integrator = Integrator::usl;
  double flip = 0.99;         // FLIP fraction of the particle velocity update (1 = pure FLIP)
  double cfl = 0.4;           // dt = cfl h / max(c_L/sqrt(f) + |v|)
  double mass_scaling = 1.0;  // f: inertia x f, clock physical
  int ppc = 2;                // particles per cell per axis
  Vec<D> gravity = Vec<D>::Zero();
};

// One material's batch: the particles that use it (storage order) and their history.
struct MaterialState {
  std::vector<std::uint32_t> index;
  std::vector<double> history;
};

struct RunControl {
  double temperature = 293.0;  // K
  double end_time = 0;         // s
  double end_strain = 0;       // die runs only
  int history_points = 400;
  int snapshots = 10;
};

template <int D>
struct Scene {
  SolverSettings<D> settings;
  RunControl control;
  Grid<D> grid;
  Particles<D> particles;
  // only with a binder_layer contact law: its per-particle data and per-node sums
  LayerData<D> layer_data;
  std::vector<std::string> material_names;
  std::vector<std::unique_ptr<Material<D>>> materials;
  std::vector<MaterialState> material_state;
  std::vector<std::string> field_names;  // deformable fields, then one per rigid body
  int deformable_fields = 0;
  std::vector<RigidBody<D>> bodies;
  ContactMatrix contact;  // laws between deformable fields ([contact] table; all weld by default)
  std::optional<Die> die;
  std::optional<PackingStats> packing_stats;  // geometric statistics of a packed specimen
  // Per particle in creation order, packed specimens only: the binder coat of the particle's
  // grain, m (0 for binder particles); read by setup_binder_layers (thickness = "coats"), then freed.
  std::vector<double> grain_coat;
  // Per particle in creation order: the body it belongs to (a packed grain's index, or for
  // [[geometry]] entries the packing's grain count plus the entry's index; -1 for binder);
  // read by setup_binder_layers (film = "integrated": one film per pair of bodies), then freed.
  std::vector<int> grain_index;
  std::string description;
};

// Orders the particles strip by strip (the solver's scatter strips, grid/strip_bins.hpp), creation
// order within a strip; material batches (in storage order), history rows and slots follow.
// Leaves the scene as it is when particles and batches are already in that order (build_scene
// orders them; the solver calls this again for scenes built by hand).
template <int D>
void order_by_strip(Scene<D>& sc);

// Keeps the particles [begin, end) of a scene ordered by strip (order_by_strip) and drops the
// rest, with their material batch entries, history rows and binder-layer data: one rank's part of
// a run decomposed over ranks, taken after the whole scene was set up (docs/architecture.md, "One
// run over many ranks"). The kept particles keep their order, and so do their batches.
template <int D>
void keep_particle_range(Scene<D>& sc, std::size_t begin, std::size_t end);

}  // namespace pbx
