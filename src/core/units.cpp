#include "core/units.hpp"

#include <cctype>
#include <cmath>
#include <charconv>
#include <map>

#include <fmt/format.h>

#include "core/error.hpp"

namespace pbx {

namespace {

struct UnitDef {
  double factor;
  Dimension dim;
};

const std::map<std::string, UnitDef, std::less<>>& unit_table() {
  static const std::map<std::string, UnitDef, std::less<>> t = {
      {"m", {1.0, dim::length}},
      {"cm", {1e-2, dim::length}},
      {"mm", {1e-3, dim::length}},
      {"um", {1e-6, dim::length}},
      {"\xC2\xB5m", {1e-6, dim::length}},
      {"nm", {1e-9, dim::length}},
      {"km", {1e3, dim::length}},
      {"kg", {1.0, dim::mass}},
      {"g", {1e-3, dim::mass}},
      {"mg", {1e-6, dim::mass}},
      {"s", {1.0, dim::time}},
      {"ms", {1e-3, dim::time}},
      {"us", {1e-6, dim::time}},
      {"\xC2\xB5s", {1e-6, dim::time}},
      {"ns", {1e-9, dim::time}},
      {"K", {1.0, dim::temperature}},
      {"mol", {1.0, Dimension{{0, 0, 0, 0, 1}}}},
      {"Pa", {1.0, dim::pressure}},
      {"kPa", {1e3, dim::pressure}},
      {"MPa", {1e6, dim::pressure}},
      {"GPa", {1e9, dim::pressure}},
      {"N", {1.0, Dimension{{1, 1, -2, 0, 0}}}},
      {"J", {1.0, dim::energy}},
      {"kJ", {1e3, dim::energy}},
      {"Hz", {1.0, dim::rate}},
  };
  return t;
}

Dimension add(Dimension a, const Dimension& b, int sign) {
  for (int i = 0; i < 5; ++i) a.e[i] += sign * b.e[i];
  return a;
}

}  // namespace

std::string Dimension::si_unit() const {
  // the derived units a deck's reader knows by name, so messages read "Pa", not "m^-1 kg s^-2"
  if (*this == dim::pressure) return "Pa";
  if (*this == dim::energy) return "J";
  if (*this == dim::molar_energy) return "J/mol";
  if (*this == dim::density) return "kg/m^3";
  if (*this == dim::velocity) return "m/s";
  if (*this == dim::acceleration) return "m/s^2";
  if (*this == dim::rate) return "1/s";
  if (*this == dim::per_temperature) return "1/K";
  static const char* names[5] = {"m", "kg", "s", "K", "mol"};
  std::string out;
  for (int i = 0; i < 5; ++i) {
    if (e[i] == 0) continue;
    if (!out.empty()) out += ' ';
    out += names[i];
    if (e[i] != 1) out += fmt::format("^{}", e[i]);
  }
  return out.empty() ? "1" : out;
}

Quantity parse_quantity(std::string_view text) {
  std::size_t i = 0;
  auto skip = [&] {
    while (i < text.size() && std::isspace(static_cast<unsigned char>(text[i]))) ++i;
  };
  skip();
  double value = 0;
  auto [ptr, ec] = std::from_chars(text.data() + i, text.data() + text.size(), value);
  if (ec == std::errc::result_out_of_range)
    throw InputError(fmt::format("the number in '{}' is beyond the range of a double (about 1e308)", text));
  if (ec != std::errc()) throw InputError(fmt::format("'{}' does not start with a number", text));
  i = static_cast<std::size_t>(ptr - text.data());
  skip();
  Quantity q{value, dim::none};
  int sign = +1;  // +1 numerator, -1 after '/'
  bool first = true;
  while (i < text.size()) {
    if (text[i] == '/' || text[i] == '*' || text[i] == '.') {
      if (text[i] == '/') sign = -1;
      ++i;
      skip();
      first = false;
      continue;
    } else if (!first && sign == -1 && text[i] == ' ') {
      ++i;
      continue;
    }
    // unit name: letters (and the UTF-8 micro sign)
    std::size_t start = i;
    while (i < text.size() &&
           (std::isalpha(static_cast<unsigned char>(text[i])) || static_cast<unsigned char>(text[i]) >= 0x80))
      ++i;
    if (start == i) {
      // "1/s" style numerator "1"
      if (text[i] == '1' && q.dimension == dim::none && first) {
        ++i;
        skip();
        continue;
      }
      throw InputError(fmt::format("cannot read the unit in '{}'", text));
    }
    std::string_view name = text.substr(start, i - start);
    int exponent = 1;
    if (i < text.size() && (text[i] == '^' || text[i] == '-' || std::isdigit(static_cast<unsigned char>(text[i])))) {
      if (text[i] == '^') ++i;
      auto [p2, ec2] = std::from_chars(text.data() + i, text.data() + text.size(), exponent);
      if (ec2 != std::errc()) throw InputError(fmt::format("bad unit exponent in '{}'", text));
      i = static_cast<std::size_t>(p2 - text.data());
    }
    const auto& table = unit_table();
    auto it = table.find(name);
    if (it == table.end()) throw InputError(fmt::format("unknown unit '{}' in '{}'", name, text));
    q.value *= std::pow(it->second.factor, sign * exponent);
    q.dimension = add(q.dimension, it->second.dim, sign * exponent);
    skip();
    first = false;
  }
  return q;
}

double to_si(std::string_view text, const Dimension& expected, std::string_view what) {
  Quantity q;
  try {
    q = parse_quantity(text);
  } catch (const InputError& e) {
    throw InputError(fmt::format("{}: {}", what, e.what()));
  }
  if (!(q.dimension == expected))
    throw InputError(
        fmt::format("{}: '{}' has units of {}, expected {}", what, text, q.dimension.si_unit(), expected.si_unit()));
  if (!std::isfinite(q.value))
    throw InputError(fmt::format("{}: '{}' overflows when converted to SI units ({})", what, text, expected.si_unit()));
  return q.value;
}

}  // namespace pbx
