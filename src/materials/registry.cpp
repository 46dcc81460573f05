// The material registry: one line per model. Adding a material = one new file + one line here.
#include <functional>
#include <map>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "core/error.hpp"
#include "io/deck.hpp"
#include "materials/material.hpp"
#include "materials/models.hpp"

namespace pbx {

namespace {
template <int D>
using Factory = std::function<std::unique_ptr<Material<D>>(const DeckTable&, const MaterialContext&)>;

template <int D>
const std::map<std::string, Factory<D>>& registry() {
  static const std::map<std::string, Factory<D>> r = {
      {"linear_elastic", make_linear_elastic<D>},
      {"elastic_linear", make_solid<D, ElasticDeviator, LinearBulkEos>},
      {"elastic_mie_gruneisen", make_solid<D, ElasticDeviator, MieGruneisenEos>},
      {"elastic_tait", make_solid<D, ElasticDeviator, TaitEos>},
      {"j2_linear", make_solid<D, J2Deviator, LinearBulkEos>},
      {"j2_mie_gruneisen", make_solid<D, J2Deviator, MieGruneisenEos>},  // TATB (paper Eq. 8-9)
      {"j2_tait", make_solid<D, J2Deviator, TaitEos>},
      {"viscoelastic_linear", make_solid<D, PronyDeviator, LinearBulkEos>},
      {"viscoelastic_mie_gruneisen", make_solid<D, PronyDeviator, MieGruneisenEos>},
      {"viscoelastic_tait", make_solid<D, PronyDeviator, TaitEos>},  // F2314 (paper Eq. 10-11)
                                                                     // registry lines for further models go here
  };
  return r;
}
}  // namespace

std::vector<std::string> material_models() {
  std::vector<std::string> out;
  for (auto& [k, v] : registry<2>()) out.push_back(k);
  return out;
}

template <int D>
std::unique_ptr<Material<D>> make_material(const DeckTable& t, const MaterialContext& ctx) {
  const std::string model = t.string("model");
  auto& r = registry<D>();
  auto it = r.find(model);
  if (it == r.end())
    t.fail("model", fmt::format("unknown material model '{}' (known: {})", model, fmt::join(material_models(), ", ")));
  return it->second(t, ctx);
}

template std::unique_ptr<Material<2>> make_material<2>(const DeckTable&, const MaterialContext&);
template std::unique_ptr<Material<3>> make_material<3>(const DeckTable&, const MaterialContext&);

}  // namespace pbx
