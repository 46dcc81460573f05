#pragma once
// Builds a scene from deck text for engine tests (2-D unless the deck says run.dimension = 3).
#include <fstream>
#include <sstream>
#include <string>

#include "io/deck.hpp"
#include "setup/build_scene.hpp"
#include "run/runner.hpp"

namespace pbx::test {

template <int D = 2>
inline Scene<D> scene_from(const std::string& text) {
  Deck deck = Deck::from_string(text, "test.toml");
  Scene<D> sc = build_scene<D>(deck);
  deck.check_unused();
  return sc;
}

// A whole file as text ("" when it cannot be read).
inline std::string slurp(const std::string& path) {
  std::ifstream f(path, std::ios::binary);
  std::stringstream ss;
  ss << f.rdbuf();
  return ss.str();
}

inline RunOptions quiet() {
  RunOptions o;
  o.progress = false;
  return o;
}

}  // namespace pbx::test
