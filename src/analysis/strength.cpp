#include "analysis/strength.hpp"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "core/error.hpp"

namespace pbx {

Strength strength_and_yield(const std::vector<double>& strain, const std::vector<double>& stress,
                            const LineFit& elastic, double linear_hi, const StrengthOptions& opt) {
  Strength s;
  double last = -HUGE_VAL;
  std::size_t imax = strain.size();
  for (std::size_t i = 0; i < strain.size(); ++i) {
    if (strain[i] > opt.max_strain || !std::isfinite(stress[i])) continue;
    last = std::max(last, strain[i]);
    if (imax == strain.size() || stress[i] > stress[imax]) imax = i;
  }
  if (imax == strain.size()) throw InputError("strength: no points at or below the strength window's end strain");
  s.window_end = last;
  s.strength = stress[imax];
  s.strain_at_strength = strain[imax];
  // "Still rising": the maximum sits in the last 2 % of the window, i.e. no peak or plateau was seen.
  s.still_rising = strain[imax] >= last - 0.02 * (last - strain.front()) && last > linear_hi;
  if (last < opt.max_strain * 0.999) {
    s.note = fmt::format("the run ends at strain {:.4g} before the strength window end {:.4g}", last, opt.max_strain);
  }

  s.plateau_hi = opt.plateau_hi.value_or(last);
  s.plateau_lo = opt.plateau_lo.value_or(linear_hi + 0.5 * (s.plateau_hi - linear_hi));
  if (!(s.plateau_hi > s.plateau_lo)) {
    s.note += (s.note.empty() ? "" : "; ") + std::string("no plateau window (the curve ends in the linear window)");
    return s;
  }
  std::vector<double> xs, ys;
  for (std::size_t i = 0; i < strain.size(); ++i) {
    if (strain[i] >= s.plateau_lo && strain[i] <= s.plateau_hi && std::isfinite(stress[i])) {
      xs.push_back(strain[i]);
      ys.push_back(stress[i]);
    }
  }
  s.plateau = fit_line(xs, ys);
  if (s.plateau.n < 3) {
    s.note += (s.note.empty() ? "" : "; ") + std::string("fewer than 3 points in the plateau window");
    return s;
  }
  if (!(elastic.slope > s.plateau.slope)) {
    s.note += (s.note.empty() ? "" : "; ") + std::string("no yield: the plateau is as steep as the elastic line");
    return s;
  }
  const double ey = (s.plateau.intercept - elastic.intercept) / (elastic.slope - s.plateau.slope);
  if (ey <= 0 || ey > s.plateau_hi) {
    s.note += (s.note.empty() ? "" : "; ") +
              fmt::format("the elastic and plateau lines cross at strain {:.4g}, outside the curve", ey);
    return s;
  }
  s.yield_strain = ey;
  s.yield_stress = elastic.intercept + elastic.slope * ey;
  return s;
}

Json Strength::to_json() const {
  Json j = Json::object();
  j.set("strength_Pa", strength);
  j.set("strain_at_strength", strain_at_strength);
  j.set("strength_window_end_strain", window_end);
  j.set("still_rising", still_rising);
  j.set("yield_stress_Pa", yield_stress ? Json(*yield_stress) : Json());
  j.set("yield_strain", yield_strain ? Json(*yield_strain) : Json());
  j.set("plateau_window", Json::numbers({plateau_lo, plateau_hi}));
  j.set("plateau_slope_Pa", plateau.n ? Json(plateau.slope) : Json());
  j.set("plateau_intercept_Pa", plateau.n ? Json(plateau.intercept) : Json());
  if (!note.empty()) j.set("note", note);
  return j;
}

}  // namespace pbx
