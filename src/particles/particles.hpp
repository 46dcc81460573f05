#pragma once
// Material points as structure-of-arrays. Storage order never changes during a run, so material
// batches and history slots stay valid; build_scene orders the particles strip by strip (the
// solver's scatter strips, grid/strip_bins.hpp) before the batches are made, so that the solver's
// per-strip loops sweep memory linearly.
#include <cstdint>
#include <algorithm>
#include <vector>

#include "core/tensor.hpp"

namespace pbx {

template <int D>
struct Particles {
  std::vector<Vec<D>> x;               // position, m
  std::vector<Vec<D>> v;               // velocity, m/s
  std::vector<double> mass;            // physical mass per unit depth (2D: kg/m), unscaled
  std::vector<double> volume0;         // reference volume (2D: m^2 per unit depth)
  std::vector<double> volume;          // current volume = J * volume0
  std::vector<Mat<D>> F;               // deformation gradient
  std::vector<Mat<D>> L;               // velocity gradient used by the last stress update, 1/s
  std::vector<Sym3> stress;            // Cauchy stress, Pa (plane strain keeps zz)
  std::vector<std::int32_t> material;  // index into the run's material list
  std::vector<std::int32_t> field;     // contact (velocity) field index
  std::vector<std::uint32_t> slot;     // history slot inside the particle's material
  // Only with a binder_layer contact law (contact/binder_layer.hpp), else empty: the reference
  // position (the layer's jump is a displacement difference) and whether the particle lies at a
  // bonded grain-grain contact (set once by build_scene).
  std::vector<Vec<D>> X0;            // m
  std::vector<std::uint8_t> bonded;  // 0 or 1
  std::vector<Vec<D>> N0;            // bonded: unit normal of its contact, towards the other grain
  std::vector<double> layer_inv_t;   // bonded: 1 / thickness of its contact's layer, 1/m (0 if not bonded)

  std::size_t size() const { return x.size(); }

  void reserve(std::size_t n) {
    x.reserve(n);
    v.reserve(n);
    mass.reserve(n);
    volume0.reserve(n);
    volume.reserve(n);
    F.reserve(n);
    L.reserve(n);
    stress.reserve(n);
    material.reserve(n);
    field.reserve(n);
    slot.reserve(n);
  }

  // Puts particle order[k] at position k (order is a permutation of 0..size()-1). In place, one
  // array at a time by following the permutation's cycles, so the peak memory of the run (the
  // footprint target) does not grow by a copy of the arrays.
  void reorder(const std::vector<std::uint32_t>& order) {
    std::vector<bool> done(order.size());
    auto permute = [&](auto& a) {
      std::fill(done.begin(), done.end(), false);
      for (std::size_t start = 0; start < order.size(); ++start) {
        if (done[start]) continue;
        auto first = a[start];
        std::size_t k = start;
        while (order[k] != start) {
          a[k] = a[order[k]];
          done[k] = true;
          k = order[k];
        }
        a[k] = first;
        done[k] = true;
      }
    };
    permute(x);
    permute(v);
    permute(mass);
    permute(volume0);
    permute(volume);
    permute(F);
    permute(L);
    permute(stress);
    permute(material);
    permute(field);
    permute(slot);
    if (!X0.empty()) permute(X0);
    if (!bonded.empty()) permute(bonded);
    if (!N0.empty()) permute(N0);
    if (!layer_inv_t.empty()) permute(layer_inv_t);
  }

  std::size_t add(const Vec<D>& pos, double vol, double m, int mat, int fld) {
    x.push_back(pos);
    v.push_back(Vec<D>::Zero());
    mass.push_back(m);
    volume0.push_back(vol);
    volume.push_back(vol);
    F.push_back(Mat<D>::Identity());
    L.push_back(Mat<D>::Zero());
    stress.push_back(Sym3{});
    material.push_back(mat);
    field.push_back(fld);
    slot.push_back(0);
    return x.size() - 1;
  }
};

}  // namespace pbx
