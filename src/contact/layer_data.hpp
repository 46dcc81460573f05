#pragma once
// The binder_layer law's own data (contact/law_binder_layer.hpp), kept beside the particles and the
// grid rather than in them: a run without that law carries none of it, and a contact law that needs
// per-contact data of its own adds a store like this one, not fields to Particles or Grid.
// - per particle, found once by setup_binder_layers: the reference position (the layer's jump is a
//   displacement difference), whether the particle lies at a bonded grain-grain contact, that
//   contact's unit normal towards the other grain, and 1 / the thickness of its layer;
// - per deformable field and node (the grid's layout, field * nodes + node), the sums the P2G
//   scatter builds from them every step and the field contact reads: sum S m (X_p - origin),
//   sum S m F_p, sum S m bonded_p, sum S m F^-T N0 (the field's contact normal), sum S m bonded_p / t_p
//   (with the bond sum, the node's mean 1/t: pair thicknesses differ).
#include <cstdint>
#include <vector>

#include "core/tensor.hpp"
#include "particles/particles.hpp"

namespace pbx {

template <int D>
struct LayerParticles {
  std::vector<Vec<D>> X0;            // m
  std::vector<std::uint8_t> bonded;  // 0 or 1
  std::vector<Vec<D>> N0;            // bonded: unit normal of its contact, towards the other grain
  std::vector<double> inv_t;         // bonded: 1 / thickness of its contact's layer, 1/m (0 if not bonded)

  bool empty() const { return bonded.empty(); }
  // follows Particles::reorder (the same permutation)
  void reorder(const std::vector<std::uint32_t>& order) {
    std::vector<bool> done;
    permute_in_place(X0, order, done);
    permute_in_place(bonded, order, done);
    permute_in_place(N0, order, done);
    permute_in_place(inv_t, order, done);
  }
  // follows Particles::keep
  void keep(std::size_t begin, std::size_t end) {
    keep_range(X0, begin, end);
    keep_range(bonded, begin, end);
    keep_range(N0, begin, end);
    keep_range(inv_t, begin, end);
  }
};

template <int D>
struct LayerSums {
  std::vector<Vec<D>> mref;
  std::vector<Mat<D>> mdef;
  std::vector<double> mbond;
  std::vector<Vec<D>> mnorm;
  std::vector<double> minvt;

  void allocate(std::size_t size) {
    mref.assign(size, Vec<D>::Zero());
    mdef.assign(size, Mat<D>::Zero());
    mbond.assign(size, 0.0);
    mnorm.assign(size, Vec<D>::Zero());
    minvt.assign(size, 0.0);
  }
  void zero(std::size_t k) {
    mref[k].setZero();
    mdef[k].setZero();
    mbond[k] = 0.0;
    minvt[k] = 0.0;
    mnorm[k].setZero();
  }
};

// film = "bonds": a spring between two particles of different bodies across their film, found once
// by setup_binder_layers (the particles are in their final storage order by then, and a run with
// bonds is not split over ranks). Force on p: K (x_q - x_p - d0), K = coef (M_b n0 n0^T + G_b (I -
// n0 n0^T)) with the law's current moduli; on q the opposite.
template <int D>
struct LayerBond {
  std::uint32_t p = 0, q = 0;
  int layer = 0;    // index into ContactMatrix::layers
  double coef = 0;  // a / (2 (t + g)): the pair's share of the film per unit modulus, m (2-D: per metre of depth)
  Vec<D> d0, n0;    // reference x_q - x_p, m, and its unit direction
};

template <int D>
struct LayerData {
  LayerParticles<D> particles;
  LayerSums<D> sums;
  std::vector<LayerBond<D>> bonds;
  long gap_particles_joined = 0;  // gap_binder = "join": binder particles in the pairs' gaps moved to a grain's field
  // the run has a binder_layer law (its sums are allocated with the grid)
  bool on() const { return !sums.mbond.empty(); }
};

}  // namespace pbx
