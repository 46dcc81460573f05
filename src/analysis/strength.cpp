#include "analysis/strength.hpp"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "core/error.hpp"

namespace pbx {

Strength strength_and_yield(const std::vector<double>& strain, const std::vector<double>& stress,
                            const LineFit& elastic, double linear_hi, const StrengthOptions& opt) {
  Strength s;
  double last = -HUGE_VAL, run_end = -HUGE_VAL;
  std::size_t imax = strain.size();
  for (std::size_t i = 0; i < strain.size(); ++i) {
    if (std::isfinite(stress[i])) run_end = std::max(run_end, strain[i]);
    if (strain[i] > opt.max_strain || !std::isfinite(stress[i])) continue;
    last = std::max(last, strain[i]);
    if (imax == strain.size() || stress[i] > stress[imax]) imax = i;
  }
  if (imax == strain.size()) throw InputError("strength: no points at or below the strength window's end strain");
  s.window_end = last;
  s.peak = stress[imax];
  s.strain_at_peak = strain[imax];
  // "Still rising": the maximum sits in the last 2 % of the window, i.e. no peak or plateau was seen.
  s.still_rising = strain[imax] >= last - 0.02 * (last - strain.front()) && last > linear_hi;
  // Only a run that stops short is worth a note: the history's last row at or below the window's end
  // lies up to one row spacing before it (0.02991 for rows every 0.01 % of strain), which is not that.
  if (run_end < opt.max_strain * 0.999) {
    s.note =
        fmt::format("the run ends at strain {:.4g} before the strength window end {:.4g}", run_end, opt.max_strain);
  }
  // The plateau mean: trapezoidal integral of the stress over [plateau_from, last] divided by its
  // length (the history is written at equal strain steps, but the mean must not depend on that).
  s.plateau_from = opt.plateau_from;
  double area = 0, first = NAN, prev_e = NAN, prev_s = NAN;
  for (std::size_t i = 0; i < strain.size(); ++i) {
    if (strain[i] < opt.plateau_from || strain[i] > last || !std::isfinite(stress[i])) continue;
    if (std::isnan(first)) first = strain[i];
    if (!std::isnan(prev_e)) area += 0.5 * (stress[i] + prev_s) * (strain[i] - prev_e);
    prev_e = strain[i], prev_s = stress[i];
  }
  s.end_stress = std::isnan(prev_e) ? stress[imax] : prev_s;
  if (!(prev_e > first)) {
    s.strength = s.peak;
    s.note += (s.note.empty() ? "" : "; ") +
              fmt::format("the curve ends before the plateau window starts at strain {:.4g}: strength is the peak",
                          opt.plateau_from);
  } else {
    s.strength = area / (prev_e - first);
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
  j["strength_Pa"] = strength;
  j["strength_definition"] =
      fmt::format("mean stress over strain [{:.4g}, {:.4g}] (the plateau level)", plateau_from, window_end);
  j["peak_strength_Pa"] = peak;
  j["strain_at_peak"] = strain_at_peak;
  j["end_stress_Pa"] = end_stress;
  j["strength_window_end_strain"] = window_end;
  j["still_rising"] = still_rising;
  j["yield_stress_Pa"] = yield_stress ? Json(*yield_stress) : Json();
  j["yield_strain"] = yield_strain ? Json(*yield_strain) : Json();
  j["plateau_window"] = json_numbers({plateau_lo, plateau_hi});
  j["plateau_slope_Pa"] = plateau.n ? Json(plateau.slope) : Json();
  j["plateau_intercept_Pa"] = plateau.n ? Json(plateau.intercept) : Json();
  if (!note.empty()) j["note"] = note;
  return j;
}

}  // namespace pbx
