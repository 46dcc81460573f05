#include "io/deck.hpp"

#include <cmath>

#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>

#include <fmt/format.h>
#include <toml++/toml.h>

#include "core/error.hpp"

namespace pbx {

struct Deck::Impl {
  toml::table root;
  std::string name, text, dir;
  mutable std::set<const toml::node*> used;
};

Deck::Deck() : impl_(std::make_unique<Impl>()) {}
Deck::Deck(Deck&&) noexcept = default;
Deck& Deck::operator=(Deck&&) noexcept = default;
Deck::~Deck() = default;

Deck Deck::from_string(const std::string& text, const std::string& name, const std::string& directory) {
  Deck d;
  d.impl_->name = name;
  d.impl_->text = text;
  d.impl_->dir = directory.empty() ? "." : directory;
  try {
    d.impl_->root = toml::parse(text, name);
  } catch (const toml::parse_error& e) {
    throw InputError(
        fmt::format("{}:{}:{}: {}", name, e.source().begin.line, e.source().begin.column, e.description()));
  }
  return d;
}

Deck Deck::from_file(const std::string& file) {
  std::ifstream in(file);
  if (!in) throw InputError(fmt::format("cannot open deck '{}'", file));
  std::stringstream ss;
  ss << in.rdbuf();
  Deck d = from_string(ss.str(), file);
  auto parent = std::filesystem::path(file).parent_path();
  d.impl_->dir = parent.empty() ? "." : parent.string();
  return d;
}

DeckTable Deck::root() const { return DeckTable(this, &impl_->root, ""); }
const std::string& Deck::name() const { return impl_->name; }
const std::string& Deck::text() const { return impl_->text; }
const std::string& Deck::directory() const { return impl_->dir; }

std::string Deck::resolve(const std::string& relative) const {
  std::filesystem::path p(relative);
  if (p.is_absolute()) return p.string();
  return (std::filesystem::path(impl_->dir) / p).lexically_normal().string();
}

namespace {
void find_unused(const toml::node& node, const std::string& path, const std::set<const toml::node*>& used,
                 const std::string& name) {
  if (auto* t = node.as_table()) {
    for (auto&& [k, v] : *t) {
      std::string p = path.empty() ? std::string(k.str()) : path + "." + std::string(k.str());
      if (!used.count(&v)) throw InputError(fmt::format("{}:{}: unknown key '{}'", name, v.source().begin.line, p));
      find_unused(v, p, used, name);
    }
  } else if (auto* a = node.as_array()) {
    std::size_t i = 0;
    for (auto& v : *a) {
      if (v.is_table()) find_unused(v, fmt::format("{}[{}]", path, i), used, name);
      ++i;
    }
  }
}
}  // namespace

void Deck::check_unused() const { find_unused(impl_->root, "", impl_->used, impl_->name); }

void DeckTable::check_unused() const {
  find_unused(*static_cast<const toml::table*>(node_), path_, deck_->impl_->used, deck_->name());
}

std::string Deck::to_json() const {
  std::stringstream ss;
  ss << toml::json_formatter{impl_->root};
  return ss.str();
}

// ---------------------------------------------------------------------------------------------
namespace {
const toml::table& tbl(const void* p) { return *static_cast<const toml::table*>(p); }
}  // namespace

std::string DeckTable::where(const std::string& key) const {
  const toml::node* n = tbl(node_).get(key);
  long line = n ? static_cast<long>(n->source().begin.line) : static_cast<long>(tbl(node_).source().begin.line);
  std::string full = path_.empty() ? key : path_ + "." + key;
  return fmt::format("{}:{}: {}", deck_->name(), line, full);
}

void DeckTable::fail(const std::string& key, const std::string& msg) const {
  throw InputError(fmt::format("{}: {}", where(key), msg));
}

bool DeckTable::has(const std::string& key) const { return tbl(node_).contains(key); }

std::vector<std::string> DeckTable::keys() const {
  std::vector<std::string> out;
  for (auto&& [k, v] : tbl(node_)) out.emplace_back(k.str());
  return out;
}

namespace {
void mark_all(const toml::node& n, std::set<const toml::node*>& used) {
  used.insert(&n);
  if (auto* t = n.as_table())
    for (auto&& [k, v] : *t) mark_all(v, used);
  else if (auto* a = n.as_array())
    for (auto& v : *a) mark_all(v, used);
}
}  // namespace

void DeckTable::accept(const std::string& key) const {
  if (auto* n = static_cast<const toml::node*>(child(key))) mark_all(*n, deck_->impl_->used);
}

const void* DeckTable::child(const std::string& key) const {
  const toml::node* n = tbl(node_).get(key);
  if (n) deck_->impl_->used.insert(n);
  return n;
}

double DeckTable::quantity(const std::string& key, const Dimension& d, std::optional<double> def) const {
  auto* n = static_cast<const toml::node*>(child(key));
  if (!n) {
    if (def) return *def;
    fail(key, fmt::format("required key missing (a quantity in {})", d.si_unit()));
  }
  double v;
  if (auto x = n->value<double>()) {
    v = *x;  // plain numbers are SI
    // No solid or liquid is lighter than 100 kg/m^3: a plain 1.9 is almost surely g/cm3 without
    // its unit. Stated, not refused (non-dimensional test decks use density 1 on purpose).
    if (d == dim::density && v > 0.0 && v < 100.0)
      fmt::print(stderr,
                 "pbxmpm: warning: {}: the plain number {:g} is read as {:g} kg/m^3 (plain numbers are SI); "
                 "write \"{:g} g/cm3\" if g/cm3 was meant\n",
                 where(key), v, v, v);
  } else if (auto s = n->value<std::string>()) {
    v = to_si(*s, d, where(key));
  } else
    fail(key, fmt::format("expected a number (SI, {}) or a string with a unit", d.si_unit()));
  // toml accepts nan and inf; no deck quantity may be either (inf would pass every "> 0" check)
  if (!std::isfinite(v)) fail(key, fmt::format("must be a finite number (got {})", v));
  return v;
}

double DeckTable::number(const std::string& key, std::optional<double> def) const {
  auto* n = static_cast<const toml::node*>(child(key));
  if (!n) {
    if (def) return *def;
    fail(key, "required key missing (a number)");
  }
  double v;
  if (auto x = n->value<double>())
    v = *x;
  else if (auto s = n->value<std::string>())
    v = to_si(*s, dim::none, where(key));
  else
    fail(key, "expected a number");
  if (!std::isfinite(v)) fail(key, fmt::format("must be a finite number (got {})", v));
  return v;
}

long DeckTable::integer(const std::string& key, std::optional<long> def) const {
  auto* n = static_cast<const toml::node*>(child(key));
  if (!n) {
    if (def) return *def;
    fail(key, "required key missing (an integer)");
  }
  if (n->is_integer()) return static_cast<long>(*n->value<int64_t>());
  fail(key, "expected an integer");
}

bool DeckTable::boolean(const std::string& key, std::optional<bool> def) const {
  auto* n = static_cast<const toml::node*>(child(key));
  if (!n) {
    if (def) return *def;
    fail(key, "required key missing (true or false)");
  }
  if (auto v = n->value<bool>()) return *v;
  fail(key, "expected true or false");
}

std::string DeckTable::string(const std::string& key, std::optional<std::string> def) const {
  auto* n = static_cast<const toml::node*>(child(key));
  if (!n) {
    if (def) return *def;
    fail(key, "required key missing (a string)");
  }
  if (auto v = n->value<std::string>()) return *v;
  fail(key, "expected a string");
}

std::vector<double> DeckTable::quantities(const std::string& key, const Dimension& d) const {
  auto* n = static_cast<const toml::node*>(child(key));
  if (!n) fail(key, "required key missing (an array of quantities)");
  auto* a = n->as_array();
  if (!a) fail(key, "expected an array");
  std::vector<double> out;
  for (auto& e : *a) {
    if (auto v = e.value<double>())
      out.push_back(*v);
    else if (auto s = e.value<std::string>())
      out.push_back(to_si(*s, d, where(key)));
    else
      fail(key, "expected an array of numbers or strings with units");
    if (!std::isfinite(out.back()))
      fail(key, fmt::format("entry {} must be a finite number (got {})", out.size() - 1, out.back()));
  }
  return out;
}

std::vector<std::string> DeckTable::strings(const std::string& key) const {
  auto* n = static_cast<const toml::node*>(child(key));
  if (!n) fail(key, "required key missing (an array of strings)");
  auto* a = n->as_array();
  if (!a) fail(key, "expected an array of strings");
  std::vector<std::string> out;
  for (auto& e : *a) {
    auto s = e.value<std::string>();
    if (!s) fail(key, "expected an array of strings");
    out.push_back(*s);
  }
  return out;
}

DeckTable DeckTable::table(const std::string& key) const {
  auto t = optional_table(key);
  if (!t) fail(key, "required table missing");
  return *t;
}

std::optional<DeckTable> DeckTable::optional_table(const std::string& key) const {
  auto* n = static_cast<const toml::node*>(child(key));
  if (!n) return std::nullopt;
  if (!n->is_table()) fail(key, "expected a table");
  return DeckTable(deck_, n->as_table(), path_.empty() ? key : path_ + "." + key);
}

std::vector<DeckTable> DeckTable::tables(const std::string& key) const {
  auto* n = static_cast<const toml::node*>(child(key));
  std::vector<DeckTable> out;
  if (!n) return out;
  auto* a = n->as_array();
  if (!a) fail(key, "expected an array of tables ([[" + key + "]])");
  std::size_t i = 0;
  for (auto& e : *a) {
    if (!e.is_table()) fail(key, "expected an array of tables ([[" + key + "]])");
    out.push_back(DeckTable(deck_, e.as_table(), fmt::format("{}[{}]", path_.empty() ? key : path_ + "." + key, i++)));
  }
  return out;
}

double DeckTable::positive(const std::string& key, const Dimension& d, std::optional<double> def) const {
  double v = quantity(key, d, def);
  if (!(v > 0)) fail(key, fmt::format("must be > 0 (got {} {})", v, d.si_unit()));
  return v;
}

double DeckTable::non_negative(const std::string& key, const Dimension& d, std::optional<double> def) const {
  double v = quantity(key, d, def);
  if (!(v >= 0)) fail(key, fmt::format("must be >= 0 (got {} {})", v, d.si_unit()));
  return v;
}

double DeckTable::in_range(const std::string& key, double lo, double hi, std::optional<double> def) const {
  double v = number(key, def);
  if (!(v >= lo && v <= hi)) fail(key, fmt::format("must lie in [{}, {}] (got {})", lo, hi, v));
  return v;
}

}  // namespace pbx
