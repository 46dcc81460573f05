#include "contact/contact_matrix.hpp"

#include <algorithm>
#include <map>
#include <utility>

#include <fmt/format.h>

#include "core/error.hpp"
#include "core/units.hpp"

namespace pbx {

bool ContactMatrix::all_weld() const {
  return std::all_of(pair.begin(), pair.end(), [](const PairLaw& p) { return p.law == ContactLaw::weld; });
}

const char* to_string(ContactLaw law) {
  switch (law) {
    case ContactLaw::weld:
      return "weld";
    case ContactLaw::frictionless:
      return "frictionless";
    case ContactLaw::coulomb:
      return "coulomb";
    case ContactLaw::adhesion:
      return "adhesion";
    case ContactLaw::binder_layer:
      return "binder_layer";
    case ContactLaw::registered:
      return "registered";
  }
  return "?";
}

}  // namespace pbx
