#pragma once
// Yield stress and compression strength of a stress-strain curve (compression positive).
//  - compression strength: the maximum stress for strain <= max_strain (default 3 %: the paper's
//    Eq. 14 peaks at 2.88 %); if the maximum is at the last point of the window the curve is
//    still rising and the value is flagged as the stress at the window end.
//  - yield: the intersection of the elastic line (fit over the linear window) and the plateau line
//    (fit over the plateau window, by default the second half of [end of linear window, max_strain]).
#include <optional>
#include <string>
#include <vector>

#include "analysis/json.hpp"
#include "analysis/least_squares.hpp"

namespace pbx {

struct StrengthOptions {
  double max_strain = 0.03;
  std::optional<double> plateau_lo, plateau_hi;
};

struct Strength {
  double strength = 0;         // Pa
  double strain_at_strength = 0;
  bool still_rising = false;   // maximum at the window end
  double window_end = 0;       // strain actually used (the run may end earlier)
  std::optional<double> yield_stress, yield_strain;
  double plateau_lo = 0, plateau_hi = 0;
  LineFit plateau;
  std::string note;
  Json to_json() const;
};

// elastic: the line fitted over the linear window, whose upper end is linear_hi.
Strength strength_and_yield(const std::vector<double>& strain, const std::vector<double>& stress,
                            const LineFit& elastic, double linear_hi, const StrengthOptions& opt);

}  // namespace pbx
