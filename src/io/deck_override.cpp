#include "io/deck_override.hpp"

#include <sstream>

#include <fmt/format.h>

#include "core/error.hpp"

namespace pbx {

void apply_override(toml::table& deck, const std::string& key, const std::string& text, const std::string& what) {
  toml::table* t = &deck;
  std::size_t start = 0, dot;
  while ((dot = key.find('.', start)) != std::string::npos) {
    const std::string part = key.substr(start, dot - start);
    if (!t->contains(part)) t->insert(part, toml::table{});
    t = (*t)[part].as_table();
    if (!t) throw InputError(fmt::format("{}: '{}' is not a table in the deck", what, part));
    start = dot + 1;
  }
  const std::string leaf = key.substr(start);
  if (leaf.empty()) throw InputError(fmt::format("{}: the key ends with '.'", what));
  toml::table v;
  try {
    v = toml::parse("v = " + text);
  } catch (const toml::parse_error&) {
    throw InputError(
        fmt::format("{}: cannot read value '{}' (TOML: a number, \"a string with its unit\", true/false, "
                    "[an, array])",
                    what, text));
  }
  t->insert_or_assign(leaf, *v.get("v"));
}

DeckOverride parse_override_option(const std::string& option_text) {
  const auto eq = option_text.find('=');
  if (eq == std::string::npos || eq == 0)
    throw InputError(
        fmt::format("--set '{}': expected KEY=VALUE (e.g. --set 'grid.cell_size=\"10 um\"')", option_text));
  return {option_text.substr(0, eq), option_text.substr(eq + 1)};
}

std::string deck_with_overrides(const std::string& text, const std::string& source,
                                const std::vector<DeckOverride>& set) {
  if (set.empty()) return text;
  toml::table deck;
  try {
    deck = toml::parse(text, source);
  } catch (const toml::parse_error& e) {
    throw InputError(fmt::format("{}:{}: {}", source, e.source().begin.line, e.description()));
  }
  for (const auto& [key, value] : set) apply_override(deck, key, value, fmt::format("--set '{}'", key));
  std::ostringstream out;
  out << fmt::format("# {} with --set {}\n", source,
                     [&] {
                       std::string s;
                       for (const auto& [k, v] : set) s += (s.empty() ? "" : ", ") + k + "=" + v;
                       return s;
                     }())
      << deck << "\n";
  return out.str();
}

}  // namespace pbx
