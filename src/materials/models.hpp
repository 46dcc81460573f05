#pragma once
// Factory declarations of every material model (one per model file), used by registry.cpp.
#include <memory>

#include "materials/material.hpp"

namespace pbx {

template <int D>
std::unique_ptr<Material<D>> make_linear_elastic(const DeckTable& t, const MaterialContext& ctx);

}  // namespace pbx
