#pragma once
// Validated access to TOML decks. Every read records the key as used; Deck::check_unused() then
// turns any key nobody read into an error naming it and its line, so a typo never passes silently.
// Quantities are SI numbers or strings with units (see core/units.hpp).
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "core/param_table.hpp"
#include "core/units.hpp"

namespace pbx {

class Deck;

// A table of a deck: the parameter interface models read (core/param_table.hpp) plus the deck's
// structure (sub-tables), which only the setup layer walks.
class DeckTable final : public ParamTable {
 public:
  // Dotted path of this table inside the deck, e.g. "materials.tatb" ("" for the root).
  const std::string& path() const override { return path_; }
  bool has(const std::string& key) const override;
  std::vector<std::string> keys() const override;

  // Required when no default is given. Errors name the key and line.
  double quantity(const std::string& key, const Dimension& d, std::optional<double> def = {}) const override;
  double number(const std::string& key, std::optional<double> def = {}) const override;
  long integer(const std::string& key, std::optional<long> def = {}) const override;
  bool boolean(const std::string& key, std::optional<bool> def = {}) const override;
  std::string string(const std::string& key, std::optional<std::string> def = {}) const override;
  std::vector<double> quantities(const std::string& key, const Dimension& d) const override;
  std::vector<std::string> strings(const std::string& key) const override;

  // Marks a key and everything under it as read whatever its type (values checked elsewhere, e.g.
  // study overrides, which may be whole arrays of tables such as "contact.pair").
  void accept(const std::string& key) const;

  DeckTable table(const std::string& key) const;  // required sub-table
  std::optional<DeckTable> optional_table(const std::string& key) const;
  std::vector<DeckTable> tables(const std::string& key) const;  // array of tables ([[key]])

  // Range checks that name the key: throw InputError unless the condition holds.
  double positive(const std::string& key, const Dimension& d, std::optional<double> def = {}) const override;
  double non_negative(const std::string& key, const Dimension& d, std::optional<double> def = {}) const override;
  double in_range(const std::string& key, double lo, double hi, std::optional<double> def = {}) const override;

  // Throws InputError "<file>:<line>: <path.key>: <msg>".
  [[noreturn]] void fail(const std::string& key, const std::string& msg) const override;
  // Throws InputError naming the first key of this table (and its sub-tables) never read: for a
  // command that reads one table of a deck whose other tables it ignores.
  void check_unused() const;
  std::string where(const std::string& key) const override;  // "file:line: path.key"

 private:
  friend class Deck;
  DeckTable(const Deck* deck, const void* node, std::string path) : deck_(deck), node_(node), path_(std::move(path)) {}
  const void* child(const std::string& key) const;  // toml::node*, marks the key used
  const Deck* deck_ = nullptr;
  const void* node_ = nullptr;  // toml::table*
  std::string path_;
};

class Deck {
 public:
  static Deck from_file(const std::string& file);
  // `directory`: the folder relative paths in the deck are resolved against.
  static Deck from_string(const std::string& text, const std::string& name = "<string>",
                          const std::string& directory = ".");
  Deck(Deck&&) noexcept;
  Deck& operator=(Deck&&) noexcept;
  ~Deck();

  DeckTable root() const;
  const std::string& name() const;       // file name used in messages
  const std::string& text() const;       // the deck's text as read
  const std::string& directory() const;  // folder of the deck file (for relative paths)
  // Throws InputError naming the first key that was never read ("unknown key").
  void check_unused() const;
  // Resolves a path written in the deck relative to the deck's folder.
  std::string resolve(const std::string& relative) const;
  // Re-serialises the whole deck as JSON (for run.json).
  std::string to_json() const;

 private:
  friend class DeckTable;
  Deck();
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace pbx
