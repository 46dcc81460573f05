#pragma once
// Physical quantities in decks: plain numbers are SI; strings carry a unit ("11.5 GPa",
// "1.934 g/cm3", "5 um", "0.3 m/s", "100 kJ/mol") and are converted to SI on reading.
#include <array>
#include <string>
#include <string_view>

namespace pbx {

// Exponents of (m, kg, s, K, mol).
struct Dimension {
  std::array<int, 5> e{0, 0, 0, 0, 0};
  bool operator==(const Dimension&) const = default;
  std::string si_unit() const;  // e.g. "Pa", "kg m^-1 s^-1"
};

namespace dim {
inline constexpr Dimension none{{0, 0, 0, 0, 0}};
inline constexpr Dimension length{{1, 0, 0, 0, 0}};
inline constexpr Dimension mass{{0, 1, 0, 0, 0}};
inline constexpr Dimension time{{0, 0, 1, 0, 0}};
inline constexpr Dimension temperature{{0, 0, 0, 1, 0}};
inline constexpr Dimension velocity{{1, 0, -1, 0, 0}};
inline constexpr Dimension acceleration{{1, 0, -2, 0, 0}};
inline constexpr Dimension pressure{{-1, 1, -2, 0, 0}};
inline constexpr Dimension density{{-3, 1, 0, 0, 0}};
inline constexpr Dimension rate{{0, 0, -1, 0, 0}};
inline constexpr Dimension per_temperature{{0, 0, 0, -1, 0}};
inline constexpr Dimension molar_energy{{2, 1, -2, 0, -1}};
inline constexpr Dimension energy{{2, 1, -2, 0, 0}};
}  // namespace dim

struct Quantity {
  double value = 0;  // SI
  Dimension dimension;
};

// Parses "<number> [unit]" (unit products with '*', '/', '.', exponents as "cm3", "m^3", "s^-1").
// Throws InputError on unknown units or malformed text.
Quantity parse_quantity(std::string_view text);

// Parses and converts to SI, checking the dimension. Throws InputError with `what` in the message.
double to_si(std::string_view text, const Dimension& expected, std::string_view what);

}  // namespace pbx
