#pragma once
// Material points as structure-of-arrays. Storage order never changes during a run, so material
// batches and history slots stay valid; build_scene orders the particles strip by strip (the
// solver's scatter strips, grid/strip_bins.hpp) before the batches are made, so that the solver's
// per-strip loops sweep memory linearly.
#include <cstddef>
#include <cstdint>
#include <algorithm>
#include <vector>

#include "core/tensor.hpp"

namespace pbx {

// Puts a[order[k]] at position k (order is a permutation of 0..size()-1; an empty array is left
// empty). In place, by following the permutation's cycles, so the peak memory of a run (the
// footprint target) does not grow by a copy of the arrays; `done` is scratch, reused across arrays.
template <class T>
void permute_in_place(std::vector<T>& a, const std::vector<std::uint32_t>& order, std::vector<bool>& done) {
  if (a.empty()) return;
  done.assign(order.size(), false);
  for (std::size_t start = 0; start < order.size(); ++start) {
    if (done[start]) continue;
    T first = a[start];
    std::size_t k = start;
    while (order[k] != start) {
      a[k] = a[order[k]];
      done[k] = true;
      k = order[k];
    }
    a[k] = first;
    done[k] = true;
  }
}

// Keeps a[begin, end) and drops the rest (an empty array is left empty).
template <class T>
void keep_range(std::vector<T>& a, std::size_t begin, std::size_t end) {
  if (a.empty()) return;
  a.erase(a.begin() + static_cast<std::ptrdiff_t>(end), a.end());
  a.erase(a.begin(), a.begin() + static_cast<std::ptrdiff_t>(begin));
  a.shrink_to_fit();
}

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
    std::vector<bool> done;
    permute_in_place(x, order, done);
    permute_in_place(v, order, done);
    permute_in_place(mass, order, done);
    permute_in_place(volume0, order, done);
    permute_in_place(volume, order, done);
    permute_in_place(F, order, done);
    permute_in_place(L, order, done);
    permute_in_place(stress, order, done);
    permute_in_place(material, order, done);
    permute_in_place(field, order, done);
    permute_in_place(slot, order, done);
  }

  // Keeps particles [begin, end) and drops the rest (a rank's part of a decomposed run).
  void keep(std::size_t begin, std::size_t end) {
    keep_range(x, begin, end);
    keep_range(v, begin, end);
    keep_range(mass, begin, end);
    keep_range(volume0, begin, end);
    keep_range(volume, begin, end);
    keep_range(F, begin, end);
    keep_range(L, begin, end);
    keep_range(stress, begin, end);
    keep_range(material, begin, end);
    keep_range(field, begin, end);
    keep_range(slot, begin, end);
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
