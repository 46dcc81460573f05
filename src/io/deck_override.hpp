#pragma once
// Deck overrides: a dotted key set to a TOML value ("grid.cell_size" = "\"10 um\""), applied to a
// parsed deck before it is read, so the result is validated like any deck (unknown keys, units,
// ranges). Used by a study's [study.set] and group values, and by `--set KEY=VALUE` on the command line.
#include <string>
#include <utility>
#include <vector>

#include <toml++/toml.h>

namespace pbx {

using DeckOverride = std::pair<std::string, std::string>;  // dotted key, TOML value text

// Sets `key` (creating missing tables) to the value `text` parses to; throws InputError naming
// `what` (e.g. "--set 'grid.cell_size'") when a part of the key is not a table or the value is not TOML.
void apply_override(toml::table& deck, const std::string& key, const std::string& text, const std::string& what);

// "KEY=VALUE" from the command line; throws InputError naming the option.
DeckOverride parse_override_option(const std::string& option_text);

// Deck text with the overrides applied (in order), for Deck::from_string.
std::string deck_with_overrides(const std::string& text, const std::string& source,
                                const std::vector<DeckOverride>& set);

}  // namespace pbx
