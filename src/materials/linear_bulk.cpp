#include "materials/linear_bulk.hpp"

#include "core/param_table.hpp"

namespace pbx {

LinearBulkEos LinearBulkEos::from_params(const ParamTable& t, const SolidSetup&) {
  return LinearBulkEos(t.positive("bulk_modulus", dim::pressure));
}

}  // namespace pbx
