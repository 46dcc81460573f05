#include "contact/contact_tally.hpp"

#include <algorithm>
#include <utility>

namespace pbx {

namespace {
// The material pair of two fields, lower material index first (-1 for a mixed field).
std::pair<int, int> materials_of(const ContactMatrix& cm, int a, int b) {
  const int ma = cm.field_material[static_cast<std::size_t>(a)], mb = cm.field_material[static_cast<std::size_t>(b)];
  return {std::min(ma, mb), std::max(ma, mb)};
}
}  // namespace

std::vector<MaterialPair> contact_material_pairs(const ContactMatrix& cm,
                                                 const std::vector<std::string>& material_names) {
  std::vector<MaterialPair> out;
  const int nm = static_cast<int>(material_names.size());
  for (int m1 = 0; m1 < nm; ++m1)
    for (int m2 = m1; m2 < nm; ++m2) {
      bool active = false;
      for (int a = 0; a < cm.fields && !active; ++a)
        for (int b = a + 1; b < cm.fields && !active; ++b) {
          active = materials_of(cm, a, b) == std::pair(m1, m2) && cm(a, b).law != ContactLaw::weld;
        }
      if (active)
        out.push_back(
            {m1, m2,
             material_names[static_cast<std::size_t>(m1)] + "_" + material_names[static_cast<std::size_t>(m2)]});
    }
  return out;
}

template <int D>
PairImpulse<D> material_pair_impulse(const ContactTally<D>& tally, const ContactMatrix& cm, const MaterialPair& mp) {
  PairImpulse<D> sum;
  for (int a = 0; a < tally.fields; ++a)
    for (int b = a + 1; b < tally.fields; ++b) {
      if (materials_of(cm, a, b) != std::pair(mp.first, mp.second)) continue;
      const PairImpulse<D>& p = tally.at(a, b);
      sum.normal += p.normal;
      sum.shear += p.shear;
      // on_first is the impulse on field a; the column reports the impulse on the first material
      const bool a_is_first = cm.field_material[static_cast<std::size_t>(a)] == mp.first;
      sum.on_first += a_is_first ? p.on_first : Vec<D>(-p.on_first);
    }
  if (mp.first == mp.second) sum.on_first.setZero();  // action and reaction inside one material
  return sum;
}

template PairImpulse<2> material_pair_impulse<2>(const ContactTally<2>&, const ContactMatrix&, const MaterialPair&);
template PairImpulse<3> material_pair_impulse<3>(const ContactTally<3>&, const ContactMatrix&, const MaterialPair&);

}  // namespace pbx
