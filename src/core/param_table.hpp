#pragma once
// A table of named parameters with units: what a model's reader sees (a material law, an EOS, a
// contact law). Models read their typed parameters from this interface and never from a deck, so
// the engine and its plug-ins depend on nothing in io/ (docs/architecture.md "Layers"); the deck's
// tables (io/deck.hpp) are one implementation, a test or a program may give another. Every read
// names the key, every failure names it and where it was given.
#include <optional>
#include <string>
#include <vector>

#include "core/units.hpp"

namespace pbx {

class ParamTable {
 public:
  virtual ~ParamTable() = default;

  // Dotted path of this table, e.g. "materials.tatb" (for messages).
  virtual const std::string& path() const = 0;
  virtual bool has(const std::string& key) const = 0;
  virtual std::vector<std::string> keys() const = 0;

  // Required when no default is given. Quantities are SI numbers or strings with units
  // (core/units.hpp); errors name the key.
  virtual double quantity(const std::string& key, const Dimension& d, std::optional<double> def = {}) const = 0;
  virtual double number(const std::string& key, std::optional<double> def = {}) const = 0;
  virtual long integer(const std::string& key, std::optional<long> def = {}) const = 0;
  virtual bool boolean(const std::string& key, std::optional<bool> def = {}) const = 0;
  virtual std::string string(const std::string& key, std::optional<std::string> def = {}) const = 0;
  virtual std::vector<double> quantities(const std::string& key, const Dimension& d) const = 0;
  virtual std::vector<std::string> strings(const std::string& key) const = 0;

  // Range checks that name the key: throw InputError unless the condition holds.
  virtual double positive(const std::string& key, const Dimension& d, std::optional<double> def = {}) const = 0;
  virtual double non_negative(const std::string& key, const Dimension& d, std::optional<double> def = {}) const = 0;
  virtual double in_range(const std::string& key, double lo, double hi, std::optional<double> def = {}) const = 0;

  // Throws InputError "<where>: <path.key>: <msg>".
  [[noreturn]] virtual void fail(const std::string& key, const std::string& msg) const = 0;
  virtual std::string where(const std::string& key) const = 0;

 protected:
  ParamTable() = default;
  ParamTable(const ParamTable&) = default;
  ParamTable& operator=(const ParamTable&) = default;
};

}  // namespace pbx
