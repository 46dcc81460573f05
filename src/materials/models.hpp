#pragma once
// Every material model the registry (registry.cpp) builds, in one place. A composed material is a
// deviatoric law plus an equation of state (solid.hpp); every pair of the two lists below is
// registered as "<deviator>_<eos>" (e.g. "j2_mie_gruneisen", "viscoelastic_tait"). Adding a law of
// either kind = its file(s) + its class named in its list (docs/extending.md). A law that is not
// such a composition registers itself with register_material() (material.hpp).
#include <algorithm>
#include <memory>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "materials/linear_bulk.hpp"
#include "materials/mie_gruneisen.hpp"
#include "materials/tait.hpp"
#include "core/param_table.hpp"
#include "materials/elastic_deviator.hpp"
#include "materials/j2_deviator.hpp"
#include "materials/material.hpp"
#include "materials/prony_deviator.hpp"
#include "materials/solid.hpp"
#include "materials/solid_setup.hpp"

namespace pbx {

template <class... T>
struct TypeList {};

using Deviators = TypeList<ElasticDeviator, J2Deviator, PronyDeviator>;
using EquationsOfState = TypeList<LinearBulkEos, MieGruneisenEos, TaitEos>;

template <int D>
std::unique_ptr<Material<D>> make_linear_elastic(const ParamTable& t, const MaterialContext& ctx);

// Keys every composed material reads, and its thermal setup (rho0 at the run temperature).
std::vector<std::string> solid_common_keys();
SolidSetup read_solid_setup(const ParamTable& t, const MaterialContext& ctx);

// A composed material from its deck table: the common keys, the deviator's and the EOS's, and no
// other (a typo is an error naming the key and the keys the model takes).
template <int D, class Dev, class Eos>
std::unique_ptr<Material<D>> make_solid(const ParamTable& t, const MaterialContext& ctx) {
  auto allowed = solid_common_keys();
  for (auto& k : Dev::keys()) allowed.push_back(k);
  for (auto& k : Eos::keys()) allowed.push_back(k);
  for (const auto& k : t.keys())
    if (std::find(allowed.begin(), allowed.end(), k) == allowed.end())
      t.fail(k, fmt::format("unknown key for model '{}' (known: {})", Solid<D, Dev, Eos>::model_name(),
                            fmt::join(allowed, ", ")));
  const SolidSetup s = read_solid_setup(t, ctx);
  return std::make_unique<Solid<D, Dev, Eos>>(s, Dev::from_params(t, s), Eos::from_params(t, s));
}

}  // namespace pbx
