// The [contact] table of a deck read into a ContactMatrix (contact/contact_matrix.hpp): the deck's
// structure (the default law, [[contact.pair]] entries naming materials) is walked here; each law
// reads its own keys through the parameter interface (core/param_table.hpp).
#include "setup/contact_deck.hpp"

#include <algorithm>
#include <map>
#include <utility>

#include <fmt/format.h>

#include "core/error.hpp"
#include "core/units.hpp"

namespace pbx {

namespace {

// Reads law / friction / adhesion from a table, under the key names given (the [contact] table
// itself uses "default" for the law, a [[contact.pair]] uses "law").
PairLaw read_law(const DeckTable& t, const std::string& law_key, std::optional<std::string> def, ContactMatrix& cm) {
  PairLaw p;
  const std::string name = t.string(law_key, std::move(def));
  if (name == "weld")
    p.law = ContactLaw::weld;
  else if (name == "frictionless")
    p.law = ContactLaw::frictionless;
  else if (name == "coulomb")
    p.law = ContactLaw::coulomb;
  else if (name == "adhesion")
    p.law = ContactLaw::adhesion;
  else if (name == "binder_layer" && law_key == "law") {
    p.law = ContactLaw::binder_layer;  // its keys: read_layer_law
    return p;
  } else if (name == "binder_layer") {
    t.fail(law_key, "binder_layer is a law for one pair of materials: give it in a [[contact.pair]] entry");
  } else if (const ContactLawReader* read = find_contact_law(name)) {
    p.law = ContactLaw::registered;  // it reads its own keys
    cm.plugins.push_back((*read)(t));
    cm.plugin_names.push_back(name);
    p.plugin = static_cast<int>(cm.plugins.size()) - 1;
    return p;
  } else {
    std::string known = "weld, frictionless, coulomb, adhesion, binder_layer";
    for (const std::string& r : registered_contact_laws()) known += ", " + r;
    t.fail(law_key, fmt::format("unknown contact law '{}' ({})", name, known));
  }

  if (p.law == ContactLaw::coulomb || p.law == ContactLaw::adhesion) {
    p.friction = t.number("friction");
    if (!(p.friction >= 0.0)) t.fail("friction", fmt::format("friction coefficient must be >= 0, got {}", p.friction));
  } else if (t.has("friction")) {
    t.fail("friction", fmt::format("the '{}' law takes no friction coefficient", name));
  }
  if (p.law == ContactLaw::adhesion) {
    p.adhesion = t.non_negative("adhesion", dim::pressure);
  } else if (t.has("adhesion")) {
    t.fail("adhesion", fmt::format("the '{}' law takes no adhesion (use law = \"adhesion\")", name));
  }
  return p;
}

}  // namespace

ContactMatrix read_contact_matrix(const std::optional<DeckTable>& table, const std::vector<int>& field_material,
                                  const std::vector<std::string>& material_names) {
  ContactMatrix cm;
  cm.fields = static_cast<int>(field_material.size());
  const std::size_t nf = field_material.size();
  cm.pair.assign(nf * nf, PairLaw{});
  cm.field_material = field_material;
  if (!table) return cm;
  const DeckTable& t = *table;

  const PairLaw def = read_law(t, "default", std::string("weld"), cm);
  const std::string normal = t.string("normals", std::string("dominant"));
  if (normal == "dominant")
    cm.normal = ContactNormal::dominant;
  else if (normal == "average")
    cm.normal = ContactNormal::average;
  else if (normal == "own")
    cm.normal = ContactNormal::own;
  else
    t.fail("normals", fmt::format("unknown normal option '{}' (dominant, average, own)", normal));
  const std::string transfer = t.string("spring_transfer", std::string("particles"));
  if (transfer == "particles")
    cm.springs_through_particles = true;
  else if (transfer == "node")
    cm.springs_through_particles = false;
  else
    t.fail("spring_transfer", fmt::format("unknown option '{}' (particles, node)", transfer));
  cm.position_cutoff = t.number("position_check", 0.0);
  if (!(cm.position_cutoff >= 0.0)) t.fail("position_check", "must be >= 0 cells (0 switches the check off)");
  // Two touching bodies put their mass centres at a node about 2/3 of a cell apart (linear hat,
  // dense particles: +-h/3); below that, contact starts only once the bodies overlap.
  if (cm.position_cutoff > 0.0 && cm.position_cutoff < 2.0 / 3.0)
    fmt::print(stderr,
               "pbxmpm: warning: contact.position_check = {:g} cells is below the ~0.67 cell at which touching "
               "bodies' mass centres sit: fields will overlap before they feel contact (docs/deck.md)\n",
               cm.position_cutoff);

  std::map<std::string, int> mat_index;
  for (std::size_t m = 0; m < material_names.size(); ++m) mat_index[material_names[m]] = static_cast<int>(m);

  std::map<std::pair<int, int>, PairLaw> overrides;
  for (const DeckTable& p : t.tables("pair")) {
    const std::vector<std::string> names = p.strings("materials");
    if (names.size() != 2) p.fail("materials", fmt::format("needs exactly two material names, got {}", names.size()));
    int idx[2];
    for (int k = 0; k < 2; ++k) {
      auto it = mat_index.find(names[static_cast<std::size_t>(k)]);
      if (it == mat_index.end())
        p.fail("materials", fmt::format("no material named '{}' in [materials]", names[static_cast<std::size_t>(k)]));
      idx[k] = it->second;
    }
    const auto key = std::minmax(idx[0], idx[1]);
    PairLaw law = read_law(p, "law", std::nullopt, cm);
    if (law.law == ContactLaw::binder_layer) {
      cm.layers.push_back(read_layer_law(p));
      law.layer = static_cast<int>(cm.layers.size()) - 1;
      law.friction = cm.layers.back().friction;
    }
    if (!overrides.emplace(key, law).second)
      p.fail("materials", fmt::format("the pair ('{}', '{}') is listed twice", names[0], names[1]));
  }

  for (std::size_t a = 0; a < nf; ++a)
    for (std::size_t b = 0; b < nf; ++b) {
      if (a == b) continue;
      PairLaw law = def;
      const int ma = field_material[a], mb = field_material[b];
      if (ma >= 0 && mb >= 0) {
        auto it = overrides.find(std::minmax(ma, mb));
        if (it != overrides.end()) law = it->second;
      }
      cm.pair[a * nf + b] = law;
    }
  return cm;
}

}  // namespace pbx
