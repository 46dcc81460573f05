#pragma once
// The impulses the field contact law exchanges between pairs of deformable fields, summed over a
// reporting interval, and their regrouping by pairs of materials: what history.csv reports as the
// contact force per material pair (impulse / interval = mean force, like the rigid-body reactions).
//
// At a node where field a meets the rest r, the impulse d_a on a is booked to the pair (a, p) with
// p the heaviest other field (the field whose law was applied). Both sides of a two-field node book
// the same exchange, so each side adds half of it; at nodes with three or more fields the split is
// this pairwise approximation (docs/theory/contact.md).
#include <string>
#include <vector>

#include "contact/contact_matrix.hpp"
#include "core/tensor.hpp"

namespace pbx {

template <int D>
struct PairImpulse {
  Vec<D> on_first = Vec<D>::Zero();  // impulse on the lower-index field from the other, N s (per m in 2-D)
  double normal = 0;                 // sum over nodes of |normal impulse|
  double shear = 0;                  // sum over nodes of |tangential impulse|
  PairImpulse& operator+=(const PairImpulse& o) {
    on_first += o.on_first;
    normal += o.normal;
    shear += o.shear;
    return *this;
  }
};

template <int D>
struct ContactTally {
  int fields = 0;
  std::vector<PairImpulse<D>> pair;  // fields x fields; only a < b is used

  explicit ContactTally(int nfields = 0)
      : fields(nfields), pair(static_cast<std::size_t>(nfields) * static_cast<std::size_t>(nfields)) {}
  PairImpulse<D>& at(int a, int b) {
    return pair[static_cast<std::size_t>(a) * static_cast<std::size_t>(fields) + static_cast<std::size_t>(b)];
  }
  const PairImpulse<D>& at(int a, int b) const {
    return pair[static_cast<std::size_t>(a) * static_cast<std::size_t>(fields) + static_cast<std::size_t>(b)];
  }
  ContactTally& operator+=(const ContactTally& o) {
    for (std::size_t k = 0; k < pair.size(); ++k) pair[k] += o.pair[k];
    return *this;
  }
  void clear() { pair.assign(pair.size(), PairImpulse<D>{}); }
  // every double, for a sum over ranks (core/parallel.hpp)
  template <class F>
  void each_double(F&& f) {
    for (auto& p : pair) {
      for (int d = 0; d < D; ++d) f(p.on_first[d]);
      f(p.normal);
      f(p.shear);
    }
  }
};

// A pair of materials (first <= second by material index) whose fields meet under a law other than
// weld; `name` is "<first>_<second>" for the history columns.
struct MaterialPair {
  int first = 0, second = 0;
  std::string name;
};

// The material pairs that get history columns: every pair of materials with at least one pair of
// fields under a non-weld law (fields that mix materials are not attributed).
std::vector<MaterialPair> contact_material_pairs(const ContactMatrix& cm,
                                                 const std::vector<std::string>& material_names);

// Sums a field tally into one material pair: normal and shear magnitudes, and the net impulse on
// `first`'s fields from `second`'s (meaningful only when first != second).
template <int D>
PairImpulse<D> material_pair_impulse(const ContactTally<D>& tally, const ContactMatrix& cm, const MaterialPair& mp);

}  // namespace pbx
