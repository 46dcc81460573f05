#include "materials/elastic_deviator.hpp"

#include "core/param_table.hpp"

namespace pbx {

ElasticDeviator ElasticDeviator::from_params(const ParamTable& t, const SolidSetup&) {
  return ElasticDeviator(t.positive("shear_modulus", dim::pressure));
}

}  // namespace pbx
