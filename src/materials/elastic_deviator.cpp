#include "materials/elastic_deviator.hpp"

#include "io/deck.hpp"

namespace pbx {

ElasticDeviator ElasticDeviator::from_deck(const DeckTable& t, const SolidSetup&) {
  return ElasticDeviator(t.positive("shear_modulus", dim::pressure));
}

}  // namespace pbx
