#include "solver/scene.hpp"

#include <algorithm>
#include <numeric>
#include <stdexcept>

#include "core/error.hpp"
#include "grid/strip_bins.hpp"

namespace pbx {

// The solver's scatter and gather visit particles strip by strip; stored in that order, each
// strip is one linear sweep of every particle array (the hardware prefetchers follow it), where
// creation order (row-major over the whole specimen) made every strip a series of short runs.
// Within a strip the order is unchanged, so the sum order at every node, and with it every
// result, is the same as with creation order.
template <int D>
void order_by_strip(Scene<D>& sc) {
  auto& P = sc.particles;
  StripBins strips;
  strips.setup(sc.grid.n[0] - 1);
  const double inv_h = 1.0 / sc.grid.h;
  const std::size_t np = P.size();
  std::vector<long> strip(np);
  for (std::size_t p = 0; p < np; ++p) strip[p] = strips.strip_of((P.x[p][0] - sc.grid.origin[0]) * inv_h);
  // the solver also needs every batch in storage order (a strip's particles of one material are
  // then a contiguous part of the batch)
  bool batches_in_order = true;
  for (const auto& st : sc.material_state)
    batches_in_order = batches_in_order && std::is_sorted(st.index.begin(), st.index.end());
  const bool strips_in_order = std::is_sorted(strip.begin(), strip.end());
  if (strips_in_order && batches_in_order) return;
  if (!strips_in_order) {
    std::vector<std::uint32_t> order(np);
    std::iota(order.begin(), order.end(), 0u);
    std::stable_sort(order.begin(), order.end(), [&](std::uint32_t a, std::uint32_t b) { return strip[a] < strip[b]; });
    P.reorder(order);
    sc.layer_data.particles.reorder(order);
    if (!sc.layer_data.bonds.empty()) {  // the pairs follow their particles to their new places
      std::vector<std::uint32_t> place(np);
      for (std::size_t k = 0; k < np; ++k) place[order[k]] = static_cast<std::uint32_t>(k);
      for (auto& b : sc.layer_data.bonds) b.p = place[b.p], b.q = place[b.q];
    }
    // the per-particle data the layers' setup reads move with the particles
    const auto permute = [&](auto& v) {
      if (v.empty()) return;
      std::remove_reference_t<decltype(v)> moved(np);
      for (std::size_t k = 0; k < np; ++k) moved[k] = v[order[k]];
      v = std::move(moved);
    };
    permute(sc.grain_coat);
    permute(sc.grain_index);
  }
  // batches in the new storage order; a particle's history row moves with it (slot = old row)
  for (std::size_t m = 0; m < sc.material_state.size(); ++m) {
    auto& st = sc.material_state[m];
    const std::size_t hs = static_cast<std::size_t>(sc.materials[m]->history_size());
    std::vector<double> history(st.history.size());
    st.index.clear();
    for (std::size_t p = 0; p < np; ++p) {
      if (P.material[p] != static_cast<int>(m)) continue;
      const std::size_t k = st.index.size();
      std::copy_n(st.history.begin() + static_cast<long>(P.slot[p] * hs), hs,
                  history.begin() + static_cast<long>(k * hs));
      P.slot[p] = static_cast<std::uint32_t>(k);
      st.index.push_back(static_cast<std::uint32_t>(p));
    }
    st.history = std::move(history);
  }
}

template <int D>
void keep_particle_range(Scene<D>& sc, std::size_t begin, std::size_t end) {
  auto& P = sc.particles;
  if (begin > end || end > P.size()) throw std::invalid_argument("keep_particle_range: range outside the particles");
  // each batch is in storage order (order_by_strip), so the kept particles of a material are a
  // contiguous part of its batch, and their history rows the same part of its history
  for (const auto& st : sc.material_state)
    if (!std::is_sorted(st.index.begin(), st.index.end()))
      throw std::invalid_argument("keep_particle_range: the scene is not ordered by strip");
  for (std::size_t m = 0; m < sc.material_state.size(); ++m) {
    auto& st = sc.material_state[m];
    const std::size_t hs = static_cast<std::size_t>(sc.materials[m]->history_size());
    const auto lo = static_cast<std::size_t>(
        std::lower_bound(st.index.begin(), st.index.end(), static_cast<std::uint32_t>(begin)) - st.index.begin());
    const auto hi = static_cast<std::size_t>(
        std::lower_bound(st.index.begin(), st.index.end(), static_cast<std::uint32_t>(end)) - st.index.begin());
    for (std::size_t k = lo; k < hi; ++k) P.slot[st.index[k]] -= static_cast<std::uint32_t>(lo);
    keep_range(st.index, lo, hi);
    for (auto& i : st.index) i -= static_cast<std::uint32_t>(begin);
    if (hs > 0) keep_range(st.history, lo * hs, hi * hs);
  }
  if (!sc.layer_data.bonds.empty())
    throw InputError(
        "contact: film = \"bonds\" is not built for a run over MPI ranks (its pairs join particles "
        "that ranks would hold apart); run it on one process");
  P.keep(begin, end);
  sc.layer_data.particles.keep(begin, end);
  keep_range(sc.grain_coat, begin, end);
  keep_range(sc.grain_index, begin, end);
}

template void order_by_strip<2>(Scene<2>&);
template void order_by_strip<3>(Scene<3>&);
template void keep_particle_range<2>(Scene<2>&, std::size_t, std::size_t);
template void keep_particle_range<3>(Scene<3>&, std::size_t, std::size_t);

}  // namespace pbx
