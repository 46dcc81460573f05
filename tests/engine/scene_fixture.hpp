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

// Keeps the particles for which keep(x) holds and rebuilds the particle arrays and the material
// batches the way build_scene does (a body cut by symmetry planes: the Hertz tests).
template <int D, class Keep>
void keep_particles(Scene<D>& sc, Keep keep) {
  Particles<D> kept;
  const auto& P = sc.particles;
  for (std::size_t p = 0; p < P.size(); ++p)
    if (keep(P.x[p])) kept.add(P.x[p], P.volume0[p], P.mass[p], P.material[p], P.field[p]);
  sc.particles = std::move(kept);
  for (std::size_t m = 0; m < sc.materials.size(); ++m) {
    auto& st = sc.material_state[m];
    st.index.clear();
    for (std::size_t p = 0; p < sc.particles.size(); ++p)
      if (sc.particles.material[p] == static_cast<int>(m)) {
        sc.particles.slot[p] = static_cast<std::uint32_t>(st.index.size());
        st.index.push_back(static_cast<std::uint32_t>(p));
      }
    const int hs = sc.materials[m]->history_size();
    st.history.assign(st.index.size() * static_cast<std::size_t>(hs), 0.0);
    for (std::size_t k = 0; k < st.index.size(); ++k) sc.materials[m]->init_history(st.history.data() + k * hs);
  }
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
