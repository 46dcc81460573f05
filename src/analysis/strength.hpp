#pragma once
// Yield stress and compression strength of a stress-strain curve (compression positive).
//  - compression strength, as the paper reads its Table 3 on its curves: the plateau level, the mean
//    stress over [plateau_from, max_strain] (defaults 0.5 %, the end of the paper's linear stage,
//    and 3 %): the paper's own Eq. 14 averages 1.011 sigma_c there. Beside it the peak (the
//    maximum up to max_strain; Eq. 14 peaks at 1.060 sigma_c at 2.88 %) and the end value; if the
//    peak sits at the end of the window the curve is still rising: no plateau was seen.
//  - yield: the intersection of the elastic line (fit over the linear window) and the plateau line
//    (fit over the plateau window, by default the second half of [end of linear window, max_strain]).
#include <optional>
#include <string>
#include <vector>

#include "io/json.hpp"
#include "analysis/least_squares.hpp"

namespace pbx {

struct StrengthOptions {
  double max_strain = 0.03;
  double plateau_from = 0.005;  // where the plateau mean (the strength) starts
  std::optional<double> plateau_lo, plateau_hi;
};

struct Strength {
  double strength = 0;      // Pa: the plateau mean over [plateau_from, window_end]
  double plateau_from = 0;  // strain where that mean starts
  double peak = 0;          // Pa: the maximum up to window_end
  double strain_at_peak = 0;
  double end_stress = 0;      // Pa: at window_end
  bool still_rising = false;  // peak at the window end
  double window_end = 0;      // strain actually used (the run may end earlier)
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
