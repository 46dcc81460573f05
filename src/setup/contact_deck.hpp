#pragma once
// Reading a deck's [contact] table (setup/contact_deck.cpp).
#include <optional>
#include <string>
#include <vector>

#include "contact/contact_matrix.hpp"
#include "io/deck.hpp"

namespace pbx {

// Reads the optional [contact] table. field_material[f] is the material index of field f's
// particles (-1 when a field mixes materials: it then uses the default law).
ContactMatrix read_contact_matrix(const std::optional<DeckTable>& table, const std::vector<int>& field_material,
                                  const std::vector<std::string>& material_names);

}  // namespace pbx
