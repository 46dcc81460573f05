#include "eos/linear_bulk.hpp"

#include "io/deck.hpp"

namespace pbx {

LinearBulkEos LinearBulkEos::from_deck(const DeckTable& t, const SolidSetup&) {
  return LinearBulkEos(t.positive("bulk_modulus", dim::pressure));
}

}  // namespace pbx
