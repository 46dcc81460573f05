#pragma once
// Builds a 2-D scene from deck text for engine tests.
#include <fstream>
#include <sstream>
#include <string>

#include "io/deck.hpp"
#include "solver/runner.hpp"

namespace pbx::test {

inline Scene<2> scene_from(const std::string& text) {
  Deck deck = Deck::from_string(text, "test.toml");
  Scene<2> sc = build_scene<2>(deck);
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
