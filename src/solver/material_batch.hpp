#pragma once
// The batch a material law updates: `count` particles of its index from `first` on, with the
// particles' arrays and the batch's slice of the material's history. The step's stress update and
// the fused USL pass both hand their chunks to the laws through it.
#include <cstdint>
#include <span>

#include "materials/material.hpp"
#include "particles/particles.hpp"
#include "solver/scene.hpp"

namespace pbx {

template <int D>
inline MaterialBatch<D> material_batch(Particles<D>& P, MaterialState& state, int history_size, long first, long count,
                                       double dt) {
  MaterialBatch<D> batch;
  batch.index = std::span<const std::uint32_t>(state.index.data() + first, static_cast<std::size_t>(count));
  batch.L = P.L.data();
  batch.F = P.F.data();
  batch.mass = P.mass.data();
  batch.volume = P.volume.data();
  batch.volume0 = P.volume0.data();
  batch.stress = P.stress.data();
  batch.history = state.history.data() + first * history_size;
  batch.dt = dt;
  return batch;
}

}  // namespace pbx
