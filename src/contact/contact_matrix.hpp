#pragma once
// Which contact law acts between each pair of deformable velocity fields. The deck states laws per
// pair of *materials* ([contact] table); fields inherit the law of their materials, so two TATB
// grains on different fields (colours) use the ("tatb", "tatb") entry.
#include <memory>
#include <string>
#include <vector>

#include "contact/binder_layer.hpp"
#include "contact/law_registry.hpp"

namespace pbx {

// The built-in laws (one file each: contact/law_weld.hpp, law_coulomb.hpp for frictionless, coulomb
// and adhesion, law_binder_layer.hpp) and `registered`, a law registered by name at run time
// (contact/law_registry.hpp). binder_layer: a spring interface standing for an unresolved binder
// layer (contact/binder_layer.hpp) where both sides are bonded; Coulomb with `friction` elsewhere.
enum class ContactLaw { weld, frictionless, coulomb, adhesion, binder_layer, registered };

// Outward normal of field a at a node (see docs/theory/contact.md):
//   dominant: from the volume gradient of whichever side (a or the rest) has the larger |grad V|,
//             the other side antiparallel (default);
//   average:  n_a proportional to grad V_a - grad V_rest;
//   own:      n_a = grad V_a / |grad V_a| (no pairing of normals); grad V points out of a field.
enum class ContactNormal { dominant, average, own };

struct PairLaw {
  ContactLaw law = ContactLaw::weld;
  double friction = 0;  // Coulomb coefficient mu
  double adhesion = 0;  // shear adhesion S_a, Pa
  int layer = -1;       // binder_layer: index into ContactMatrix::layers
  int plugin = -1;      // registered: index into ContactMatrix::plugins
};

struct ContactMatrix {
  int fields = 0;                   // deformable fields covered
  std::vector<PairLaw> pair;        // fields x fields, symmetric
  std::vector<int> field_material;  // material index of each field's particles (-1: mixed)
  ContactNormal normal = ContactNormal::dominant;
  double position_cutoff = 0;  // displacement check, cells; 0 = off
  // An axis along which every body is uniform (a 2-D packing extruded through a 3-D die), -1 for
  // none: every interface normal then lies across it, and the volume gradients' component along it
  // (the field ending at the die's front and back walls, a cell or two away) is left out of normals.
  int extruded_axis = -1;
  // binder_layer springs hand their impulses to the momenta through the particles that define
  // their jumps (the work-conjugate force, Solver::spring_impulses_through_particles); false: at
  // the node alone (the code until 2026-12-06)
  bool springs_through_particles = true;
  std::vector<LayerLaw> layers;  // the binder_layer laws of the [[contact.pair]] entries
  // the registered laws the deck names, each built from its table, and the names it gave them
  std::vector<std::shared_ptr<const ContactLawPlugin>> plugins;
  std::vector<std::string> plugin_names;

  const PairLaw& operator()(int a, int b) const {
    return pair[static_cast<std::size_t>(a) * static_cast<std::size_t>(fields) + static_cast<std::size_t>(b)];
  }
  // True when every pair welds: the solver then takes the single-velocity fast path.
  bool all_weld() const;
  bool has_layers() const { return !layers.empty(); }
  // Sets every binder_layer law's stiffnesses to their values at time t.
  void layers_at(double t) {
    for (auto& l : layers) l.at_time(t);
  }
};

const char* to_string(ContactLaw law);

}  // namespace pbx
