#pragma once
// Whole-string number parsing for command-line options and hand-editable files: std::stod reads
// a prefix ("0.4abc" -> 0.4) and accepts "nan"/"inf", so every caller needing a real value would
// have to repeat the same checks.
#include <cmath>
#include <optional>
#include <stdexcept>
#include <string>

namespace pbx {

// The finite number `text` holds in full, or nothing.
inline std::optional<double> parse_finite(const std::string& text) {
  std::size_t used = 0;
  double v = 0;
  try {
    v = std::stod(text, &used);
  } catch (const std::exception&) {
    return std::nullopt;
  }
  if (used != text.size() || !std::isfinite(v)) return std::nullopt;
  return v;
}

}  // namespace pbx
