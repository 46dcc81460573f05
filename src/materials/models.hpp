#pragma once
// Factory declarations of every material model, used by registry.cpp.
#include <memory>
#include <string>
#include <vector>

#include "materials/material.hpp"
#include "materials/solid_setup.hpp"

namespace pbx {

template <int D>
std::unique_ptr<Material<D>> make_linear_elastic(const DeckTable& t, const MaterialContext& ctx);

// Composed materials (solid.hpp): deviatoric law Dev + equation of state Eos, registered under the
// name "<Dev::name>_<Eos::name>", e.g. "j2_mie_gruneisen", "viscoelastic_tait".
class ElasticDeviator;
class J2Deviator;
class PronyDeviator;
class LinearBulkEos;
class MieGruneisenEos;
class TaitEos;
template <int D, class Dev, class Eos>
std::unique_ptr<Material<D>> make_solid(const DeckTable& t, const MaterialContext& ctx);

// Keys every composed material reads, and its thermal setup (rho0 at the run temperature).
std::vector<std::string> solid_common_keys();
SolidSetup read_solid_setup(const DeckTable& t, const MaterialContext& ctx);

}  // namespace pbx
