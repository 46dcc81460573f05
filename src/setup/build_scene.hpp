#pragma once
// Building a scene (solver/scene.hpp) from a validated deck.
#include "io/deck.hpp"
#include "solver/scene.hpp"

namespace pbx {

// Whether building a scene prints its notes and warnings (re-colouring, shrunk grains, the
// particles' porosity, rigid bodies over particles) to stderr. A study builds every run's scene
// once to check it before starting and again when the run starts: it checks quietly, so each note
// is printed once per run.
enum class SceneNotes { print, quiet };

// The deck's run.dimension: 2 (plane strain, the default) or 3. A caller builds build_scene<D>
// with it; build_scene<D> refuses a deck of the other dimension.
int deck_dimension(const Deck& deck);

// Builds a scene from a deck; every key is validated (unknown keys are errors).
template <int D>
Scene<D> build_scene(const Deck& deck, SceneNotes notes = SceneNotes::print);

}  // namespace pbx
