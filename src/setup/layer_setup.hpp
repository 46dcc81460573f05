#pragma once
// Scene set-up of the binder_layer contact law (contact/binder_layer.hpp): the layer stiffnesses
// from the binder material at the run's temperature, the particles' reference positions, and the
// bond flags that say where the law acts.
#include "io/deck.hpp"
#include "solver/scene.hpp"

namespace pbx {

// For a scene whose contact matrix has binder_layer laws (a no-op otherwise); `root` is the deck
// the scene was built from. Bond flags: a particle is "touching" when a particle of another field
// with a binder_layer law against its own lies within one particle spacing (times 1.01) plus the
// law's bond_gap; a particle is bonded when a touching particle of its own field lies within two
// cells, i.e. within the support of every node that sees the contact; it carries the contact's
// normal (the mean direction from the touching particles to the other side). The node law acts where
// most of the mass of both sides is bonded, so grains that face each other across a pore wider
// than bond_gap are not glued together (they meet by Coulomb contact).
template <int D>
void setup_binder_layers(Scene<D>& sc, const DeckTable& root);

}  // namespace pbx
