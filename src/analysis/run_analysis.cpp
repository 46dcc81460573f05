#include "analysis/run_analysis.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <tuple>
#include <utility>

#include <fmt/format.h>

#include "analysis/confined_moduli.hpp"
#include "analysis/linear_window.hpp"
#include "analysis/strength.hpp"
#include "analysis/stress_strain_curve.hpp"
#include "core/error.hpp"
#include "io/deck.hpp"

namespace fs = std::filesystem;

namespace pbx {

namespace {

double number_or(const Json* j, const std::string& key, double def) {
  if (!j) return def;
  const Json* v = json_find(*j, key);
  return v && v->is_number() ? json_number(*v) : def;
}

Json discrepancy_json(const CurveDiscrepancy& d) {
  Json j = Json::object();
  j["rms_relative"] = d.rms_relative;
  j["max_relative"] = d.max_relative;
  j["points"] = d.points;
  return j;
}

Json thinned_curve(const StressStrainCurve& c, int target) {
  const std::size_t stride = std::max<std::size_t>(1, c.size() / std::size_t(std::max(1, target)));
  std::vector<std::size_t> keep;
  for (std::size_t i = 0; i < c.size(); i += stride) keep.push_back(i);
  if (!keep.empty() && keep.back() != c.size() - 1) keep.push_back(c.size() - 1);
  auto pick = [&](const std::vector<double>& v) {
    std::vector<double> out;
    out.reserve(keep.size());
    for (auto i : keep) out.push_back(v[i]);
    return json_numbers(out);
  };
  Json j = Json::object();
  j["strain"] = pick(c.strain);
  j["punch_stress_Pa"] = pick(c.punch_stress);
  j["minus_syy_Pa"] = pick(c.vol_axial);
  j["wall_stress_Pa"] = pick(c.wall_stress);
  j["minus_sxx_Pa"] = pick(c.vol_lateral);
  j["minus_szz_Pa"] = pick(c.vol_out_of_plane);
  j["ke_ie"] = pick(c.ke_ie);
  return j;
}

// Growth of the field-overlap area against the box area the punch took away (width x
// displacement): the share of the compaction that went into grains passing into each other instead
// of closing pores or compressing the solids; at the end of the run and at the end of the linear
// window (the moduli come from the latter). Null without the history column.
Json interpenetration_json(const StressStrainCurve& c, double width, double height, double window_hi,
                           const AnalysisOptions& opt, std::vector<std::string>& warnings) {
  if (c.field_overlap.empty() || c.size() == 0) return Json();
  Json j = Json::object();
  const double box = width * height, a0 = c.field_overlap.front();
  auto share_at = [&](std::size_t i) {
    const double lost = c.strain[i] * box;
    return std::isfinite(lost) && lost > 0 ? (c.field_overlap[i] - a0) / lost : std::nan("");
  };
  std::size_t iw = 0;  // last row inside the linear window
  for (std::size_t i = 0; i < c.size(); ++i)
    if (c.strain[i] <= window_hi) iw = i;
  const std::size_t ie = c.size() - 1;
  const double share_end = share_at(ie), share_window = share_at(iw);
  j["overlap_start_m2_per_m"] = a0;
  j["overlap_end_m2_per_m"] = c.field_overlap[ie];
  j["at_strain"] = c.strain[ie];
  j["growth_fraction_of_box"] = (c.field_overlap[ie] - a0) / box;
  j["share_of_compaction"] = std::isfinite(share_end) ? Json(share_end) : Json();
  j["share_of_compaction_at_window_end"] = std::isfinite(share_window) ? Json(share_window) : Json();
  j["window_end_strain"] = c.strain[iw];
  j["limit"] = opt.overlap_limit;
  const double worst = std::fmax(share_end, share_window);  // fmax ignores a NaN side
  const bool flagged = std::isfinite(worst) && worst > opt.overlap_limit;
  j["flagged"] = flagged;
  if (flagged) {
    warnings.push_back(
        fmt::format("grains pass into each other: the overlap of different fields' particle domains "
                    "takes {:.3g} % of the compaction at the end of the linear window and {:.3g} % "
                    "at the end of the run (limit {:.3g} %)",
                    100 * share_window, 100 * share_end, 100 * opt.overlap_limit));
  }
  return j;
}

// Energy balance: the punch is the only body that does work (the walls are fixed), and friction,
// nodal contact and PIC damping only take energy away, so kinetic energy plus stress work (which
// holds the stored energy and the plastic and viscous dissipation) cannot exceed the punch work. A
// ratio above 1 + energy_gain_limit from the linear window's start is energy the discretisation
// made (docs/theory/analysis.md). Null without the energy columns (runs of older versions).
Json energy_balance_json(const StressStrainCurve& c, double from, double window_hi, const AnalysisOptions& opt,
                         std::vector<std::string>& warnings) {
  if (c.punch_work.empty() || c.size() == 0) return Json();
  double worst = -HUGE_VAL, at = std::nan(""), at_window = std::nan(""), at_end = std::nan("");
  for (std::size_t i = 0; i < c.size(); ++i) {
    if (c.strain[i] < from || !(c.punch_work[i] > 0)) continue;
    const double r = (c.kinetic[i] + c.internal[i]) / c.punch_work[i];
    if (!std::isfinite(r)) continue;
    if (r > worst) worst = r, at = c.strain[i];
    if (c.strain[i] <= window_hi) at_window = r;
    at_end = r;
  }
  if (!std::isfinite(worst)) return Json();
  Json j = Json::object();
  j["max_ratio"] = worst;
  j["at_strain"] = at;
  j["ratio_at_window_end"] = std::isfinite(at_window) ? Json(at_window) : Json();
  j["ratio_at_end"] = at_end;
  j["limit"] = 1.0 + opt.energy_gain_limit;
  const bool flagged = worst > 1.0 + opt.energy_gain_limit;
  j["flagged"] = flagged;
  // Where the energy went at the end of the run: each part of the dissipation over the punch work
  // (a material's part above 1 alone is energy the discretisation made and the part then spent), and the
  // fastest particle against the punch from the window's start (a local instability moves a few
  // particles tens of times faster than the punch while the specimen creeps).
  std::string where;
  const std::size_t last = c.size() - 1;
  if (!c.dissipation_parts.empty() && c.punch_work[last] > 0) {
    Json parts = Json::object();
    for (const auto& [name, v] : c.dissipation_parts) {
      parts[name] = v[last] / c.punch_work[last];
      where += fmt::format("{}{} {:.2g}", where.empty() ? "; at the end the dissipation is " : ", ", name,
                           v[last] / c.punch_work[last]);
    }
    j["dissipated_over_punch_work_at_end"] = parts;  // materials by name, then "contact"
    where += " x the punch work";
    // The contact's part is the kinetic energy its exchanges remove at the grid nodes, which the next
    // transfer partly restores: an upper bound (docs/theory/contact.md), 3-7 x the punch work in the
    // paper studies. Said where it alone passes the punch work, so that it is not read as an energy.
    const auto contact = std::find_if(c.dissipation_parts.begin(), c.dissipation_parts.end(),
                                      [](const auto& part) { return part.first == "contact"; });
    if (contact != c.dissipation_parts.end() && contact->second[last] > c.punch_work[last])
      where +=
          " (the contact's part is the kinetic energy its exchanges remove at the grid nodes, an upper "
          "bound that is no energy measure here)";
  }
  if (!c.max_particle_speed.empty() && c.punch_velocity.size() == c.size()) {
    double vmax = 0, vat = std::nan(""), vpunch = 0;
    for (std::size_t i = 0; i < c.size(); ++i) {
      vpunch = std::max(vpunch, std::abs(c.punch_velocity[i]));
      if (c.strain[i] >= from && c.max_particle_speed[i] > vmax) vmax = c.max_particle_speed[i], vat = c.strain[i];
    }
    j["max_particle_speed_m_s"] = vmax;
    j["max_particle_speed_at_strain"] = std::isfinite(vat) ? Json(vat) : Json();
    if (vpunch > 0 && std::isfinite(vat)) {
      j["max_particle_speed_over_punch"] = vmax / vpunch;
      where +=
          fmt::format("; the fastest particle moves {:.3g} x the punch speed (at strain {:.4g})", vmax / vpunch, vat);
    }
  }
  if (flagged) {
    warnings.push_back(
        fmt::format("energy not conserved: kinetic energy plus stress work reach {:.3g} x the punch "
                    "work at strain {:.4g} (limit {:.3g}): the discretisation adds energy (a local "
                    "instability or a non-conservative contact law){}",
                    worst, at, 1.0 + opt.energy_gain_limit, where));
  }
  return j;
}

}  // namespace

AnalysisOptions AnalysisOptions::from_deck(const DeckTable& t) {
  AnalysisOptions o;
  if (t.has("linear_window")) {
    auto w = t.quantities("linear_window", dim::none);
    if (w.size() != 2) t.fail("linear_window", "expected [lo, hi] (strain)");
    if (!(w[1] > w[0] && w[0] >= 0)) t.fail("linear_window", fmt::format("[{}, {}]: needs 0 <= lo < hi", w[0], w[1]));
    o.window_lo = w[0];
    o.window_hi = w[1];
  }
  if (t.has("plateau_window")) {
    auto w = t.quantities("plateau_window", dim::none);
    if (w.size() != 2) t.fail("plateau_window", "expected [lo, hi] (strain)");
    if (!(w[1] > w[0] && w[0] >= 0)) t.fail("plateau_window", fmt::format("[{}, {}]: needs 0 <= lo < hi", w[0], w[1]));
    o.plateau_lo = w[0];
    o.plateau_hi = w[1];
  }
  o.window_signal = t.string("window_signal", o.window_signal);
  if (o.window_signal != "volume_average" && o.window_signal != "punch") {
    t.fail("window_signal", "must be \"volume_average\" or \"punch\"");
  }
  o.window_tolerance = t.in_range("window_tolerance", 1e-6, 1.0, o.window_tolerance);
  const long min_points = t.integer("window_min_points", o.window_min_points);  // checked before the cast
  if (min_points < 3 || min_points > 1000000)
    t.fail("window_min_points", fmt::format("must be in [3, 1000000] (got {})", min_points));
  o.window_min_points = static_cast<int>(min_points);
  o.window_max_strain = t.in_range("window_max_strain", 1e-9, 1.0, o.window_max_strain);
  o.window_min_span = t.in_range("window_min_span", 0.0, 1.0, o.window_min_span);
  if (!(o.window_min_span < o.window_max_strain))
    t.fail("window_min_span", fmt::format("must be below window_max_strain ({})", o.window_max_strain));
  o.strength_max_strain = t.in_range("strength_max_strain", 1e-9, 1.0, o.strength_max_strain);
  o.strength_plateau_from = t.in_range("strength_plateau_from", 0.0, 1.0, o.strength_plateau_from);
  if (!(o.strength_plateau_from < o.strength_max_strain))
    t.fail("strength_plateau_from", fmt::format("must be below strength_max_strain ({})", o.strength_max_strain));
  o.ke_ie_limit = t.in_range("ke_ie_limit", 0.0, 10.0, o.ke_ie_limit);
  o.overlap_limit = t.in_range("overlap_limit", 0.0, 1.0, o.overlap_limit);
  o.window_spread_limit = t.in_range("window_spread_limit", 0.0, 10.0, o.window_spread_limit);
  o.energy_gain_limit = t.in_range("energy_gain_limit", 0.0, 10.0, o.energy_gain_limit);
  o.validate();  // every check above names its key; this one only repeats them
  return o;
}

void AnalysisOptions::validate() const {
  if (window_lo.has_value() != window_hi.has_value()) throw InputError("linear window: give both ends");
  if (window_lo && !(*window_hi > *window_lo && *window_lo >= 0)) {
    throw InputError(fmt::format("linear window [{}, {}]: needs 0 <= lo < hi", *window_lo, *window_hi));
  }
  if (plateau_lo.has_value() != plateau_hi.has_value()) throw InputError("plateau window: give both ends");
  if (plateau_lo && !(*plateau_hi > *plateau_lo && *plateau_lo >= 0)) {
    throw InputError(fmt::format("plateau window [{}, {}]: needs 0 <= lo < hi", *plateau_lo, *plateau_hi));
  }
  // The same ranges as the deck keys (from_deck), so a command-line flag cannot pass a value the
  // [analysis] table refuses.
  auto in = [](double v, double lo, double hi, const char* what) {
    if (!(v >= lo && v <= hi)) throw InputError(fmt::format("{} = {}: must be in [{}, {}]", what, v, lo, hi));
  };
  in(strength_max_strain, 1e-9, 1.0, "strength window end strain (strength_max_strain, --strength-strain)");
  in(strength_plateau_from, 0.0, 1.0, "strength_plateau_from");
  if (!(strength_plateau_from < strength_max_strain))
    throw InputError(fmt::format("strength_plateau_from = {}: must be below the strength window end strain {}",
                                 strength_plateau_from, strength_max_strain));
  in(window_max_strain, 1e-9, 1.0, "window_max_strain");
  in(window_min_span, 0.0, 1.0, "window_min_span");
  if (!(window_min_span < window_max_strain))
    throw InputError(
        fmt::format("window_min_span = {}: must be below window_max_strain ({})", window_min_span, window_max_strain));
  in(window_tolerance, 1e-6, 1.0, "window tolerance (window_tolerance, --window-tolerance)");
  in(ke_ie_limit, 0.0, 10.0, "KE/IE limit (ke_ie_limit, --ke-ie-limit)");
  in(overlap_limit, 0.0, 1.0, "overlap_limit");
  in(window_spread_limit, 0.0, 10.0, "window_spread_limit");
  in(energy_gain_limit, 0.0, 10.0, "energy_gain_limit");
  if (window_min_points < 3) throw InputError(fmt::format("window_min_points = {}: must be >= 3", window_min_points));
  if (window_signal != "volume_average" && window_signal != "punch") {
    throw InputError(fmt::format("window signal '{}': must be 'volume_average' or 'punch'", window_signal));
  }
}

Json AnalysisOptions::to_json() const {
  Json j = Json::object();
  j["linear_window"] = window_lo ? json_numbers({*window_lo, *window_hi}) : Json("automatic");
  j["window_signal"] = window_signal;
  j["window_tolerance"] = window_tolerance;
  j["window_min_points"] = window_min_points;
  j["window_max_strain"] = window_max_strain;
  j["window_min_span"] = window_min_span;
  j["strength_max_strain"] = strength_max_strain;
  j["strength_plateau_from"] = strength_plateau_from;
  j["plateau_window"] = plateau_lo ? json_numbers({*plateau_lo, *plateau_hi}) : Json("automatic");
  j["ke_ie_limit"] = ke_ie_limit;
  j["overlap_limit"] = overlap_limit;
  j["window_spread_limit"] = window_spread_limit;
  j["energy_gain_limit"] = energy_gain_limit;
  return j;
}

// How much K, G and E depend on the window: refitted over its first and its last three quarters
// (each with at least 3 points), half the range of the three fits (with the window's own) over the
// window's value. A ringing reaction read over a short window moves the moduli with single rows:
// the quick specimen's 0.2 % windows of the earlier start read E 3.12 GPa over 0.235-0.469 % strain
// and 2.66 over 0.25-0.50 % (docs/theory/analysis.md §3).
static Json window_spread_json(const StressStrainCurve& c, const LinearWindow& w, const ConfinedModuli& mod,
                               const AnalysisOptions& opt, std::vector<std::string>& warnings) {
  Json j = Json::object();
  const double span = w.hi - w.lo;
  const double cut = w.lo + 0.75 * span, from = w.lo + 0.25 * span;
  if (!(span > 0) || points_in(c.strain, w.lo, cut).size() < 3 || points_in(c.strain, from, w.hi).size() < 3) {
    j["relative"] = Json();
    j["note"] = "window too short for sub-windows";
    return j;
  }
  const ConfinedModuli a = confined_moduli(c, w.lo, cut), b = confined_moduli(c, from, w.hi);
  double worst = 0;
  std::string worst_name;
  for (const auto& [name, v0, v1, v2] : {std::tuple<const char*, double, double, double>{"K", mod.K, a.K, b.K},
                                         {"G", mod.G, a.G, b.G},
                                         {"E", mod.E, a.E, b.E}}) {
    // std::min/max over a list would skip a NaN that is not its first element
    if (!std::isfinite(v0) || !std::isfinite(v1) || !std::isfinite(v2) || v0 == 0.0) {
      j["relative"] = Json();
      j["note"] = fmt::format("{} is zero or not finite on the window or a sub-window", name);
      return j;
    }
    const double lo = std::min({v0, v1, v2}), hi = std::max({v0, v1, v2});
    Json r = Json::array();
    r.push_back(lo);
    r.push_back(hi);
    j[std::string(name) + "_range_Pa"] = r;
    const double rel = 0.5 * (hi - lo) / std::fabs(v0);
    if (rel > worst) worst = rel, worst_name = name;
  }
  Json sub = Json::array();
  for (const auto& [x0, x1] : {std::pair{w.lo, cut}, std::pair{from, w.hi}}) {
    Json r = Json::array();
    r.push_back(x0);
    r.push_back(x1);
    sub.push_back(r);
  }
  j["sub_windows"] = sub;
  j["relative"] = worst;
  j["limit"] = opt.window_spread_limit;
  const bool flagged = worst > opt.window_spread_limit;
  j["flagged"] = flagged;
  if (flagged) {
    warnings.push_back(fmt::format(
        "the moduli depend on the window: {} moves by +-{:.3g} % between the linear window and its first or "
        "last three quarters (limit {:.3g} %): the curve rings or bends inside the window",
        worst_name, 100 * worst, 100 * opt.window_spread_limit));
  }
  return j;
}

Json analyze_run(const std::string& run_dir, const AnalysisOptions& opt) {
  opt.validate();
  const fs::path dir(run_dir);
  if (fs::exists(dir) && !fs::is_directory(dir))
    throw InputError(
        fmt::format("'{}' is a file: give the run's folder (the one holding run.json and history.csv)", run_dir));
  if (!fs::is_directory(dir)) throw InputError(fmt::format("run directory '{}' does not exist", run_dir));
  const fs::path run_json = dir / "run.json", history = dir / "history.csv";
  if (!fs::exists(run_json)) throw InputError(fmt::format("{}: missing (written by 'pbxmpm run')", run_json.string()));
  if (!fs::exists(history)) throw InputError(fmt::format("{}: missing (written by 'pbxmpm run')", history.string()));
  const Json run = json_read_file(run_json.string());
  const Json* status = json_find(run, "status");
  const std::string st = status && status->is_string() ? json_string(*status) : "unknown";
  if (st != "finished" && !opt.allow_unfinished) {
    throw InputError(fmt::format("{}: status is '{}', not 'finished' (use --allow-unfinished to analyse anyway)",
                                 run_json.string(), st));
  }
  std::vector<std::string> warnings;
  const double ramp = number_or(&run, "ramp_strain", 0.0);
  if (!json_find(run, "ramp_strain")) warnings.push_back("run.json has no ramp_strain; the fits start at strain 0");

  const StressStrainCurve c = StressStrainCurve::from_history(history.string());
  if (c.size() < 3) throw InputError(fmt::format("{}: only {} rows", history.string(), c.size()));

  // The quasi-static measure: KE/IE of the motion beyond the affine velocity field behind the
  // punch (stress_strain_curve.hpp). The whole KE/IE counts the specimen's steady motion with the
  // punch, f m v^2/6, which early in the test is most of it and delayed the window's start by
  // 0.1-0.15 % strain for no dynamics (quick specimen: KE/IE 0.06-0.07 at 0.15-0.23 %, of which
  // 0.00-0.03 beyond the affine motion); the window was then 0.2 % of strain, and its moduli moved
  // by 10-15 % with a one-row change of its end (docs/theory/analysis.md §2).
  const double mass_scaling = number_or(&run, "mass_scaling", std::nan(""));
  const std::vector<double> ke_ie = ke_ie_beyond_affine(c, mass_scaling);
  const bool beyond_affine = c.mass.size() == c.size() && c.kinetic.size() == c.size() &&
                             c.internal.size() == c.size() && c.punch_velocity.size() == c.size() &&
                             mass_scaling > 0.0 && std::isfinite(mass_scaling);
  LinearWindow w;
  double settled_start = std::nan("");  // automatic window: where KE/IE settled, if after the ramp
  if (opt.window_lo) {
    w.lo = *opt.window_lo;
    w.hi = *opt.window_hi;
    w.automatic = false;
    w.points = int(points_in(c.strain, w.lo, w.hi).size());
    if (w.points < 3) {
      throw InputError(fmt::format("linear window [{}, {}] holds {} points of {}; need >= 3", w.lo, w.hi, w.points,
                                   history.string()));
    }
  } else {
    LinearWindowOptions lw;
    lw.start = std::max(ramp, 0.0);
    // The inertia of the punch's start rings on after the ramp (at mass scaling 10 and a 0.05 %
    // ramp, KE/IE beyond the affine motion falls below 5 % at 0.09-0.12 % strain): moduli are read only where the run
    // is quasi-static, from the first point after which KE/IE stays within the limit up to the window's largest strain.
    // A run that never settles there keeps the ramp's end (and is flagged).
    std::size_t last_above = c.size();
    for (std::size_t i = 0; i < c.size(); ++i)
      if (c.strain[i] > lw.start && c.strain[i] <= opt.window_max_strain && std::isfinite(ke_ie[i]) &&
          ke_ie[i] > opt.ke_ie_limit)
        last_above = i;
    if (last_above + 1 < c.size() && c.strain[last_above + 1] < opt.window_max_strain) {
      settled_start = c.strain[last_above + 1];
      lw.start = settled_start;
    }
    lw.tolerance = opt.window_tolerance;
    lw.min_points = opt.window_min_points;
    lw.max_strain = opt.window_max_strain;
    lw.min_span = opt.window_min_span;
    w = find_linear_window(c.strain, opt.window_signal == "punch" ? c.punch_stress : c.vol_axial, lw);
  }
  if (!w.note.empty()) warnings.push_back(w.note);
  const ConfinedModuli mod = confined_moduli(c, w.lo, w.hi);
  const ConfinedModuli mod_vol = confined_moduli_volume_average(c, w.lo, w.hi);

  StrengthOptions so;
  so.max_strain = opt.strength_max_strain;
  so.plateau_from = opt.strength_plateau_from;
  so.plateau_lo = opt.plateau_lo;
  so.plateau_hi = opt.plateau_hi;
  const Strength s_punch = strength_and_yield(c.strain, c.punch_stress, mod.punch, w.hi, so);
  const Strength s_vol = strength_and_yield(c.strain, c.vol_axial, mod.axial_vol, w.hi, so);
  if (s_punch.still_rising) {
    warnings.push_back(
        "the punch stress still rises at the end of the strength window: no plateau, so the strength (the mean "
        "over the plateau window) and the peak (the end value) are lower bounds of a plateau level");
  }

  Json j = Json::object();
  j["format"] = "pbxmpm-analysis-1";
  j["run_dir"] = fs::absolute(dir).lexically_normal().string();
  j["status"] = st;
  for (const char* key : {"code_version", "temperature_K", "ramp_strain", "mass_scaling", "specimen", "study"}) {
    if (const Json* v = json_find(run, key)) j[key] = *v;
  }
  // the deck's run title: a calibrated study says so there, and the report prints it
  if (const Json* deck = json_find(run, "deck"))
    if (const Json* rt = json_find(*deck, "run"))
      if (const Json* title = json_find(*rt, "title"); title && title->is_string()) j["title"] = *title;
  const Json* spec = json_find(run, "specimen");
  j["density_kg_m3"] = number_or(spec, "density_kg_m3", std::nan(""));
  j["porosity"] = number_or(spec, "porosity", std::nan(""));
  j["options"] = opt.to_json();

  Json win = Json::object();
  win["lo"] = w.lo;
  win["hi"] = w.hi;
  win["points"] = w.points;
  win["automatic"] = w.automatic;
  win["signal"] = w.automatic ? opt.window_signal : std::string("by hand");
  win["start_after_ke_ie_settled"] = std::isfinite(settled_start);
  j["linear_window"] = win;
  j["moduli"] = mod.to_json();
  j["moduli_window_spread"] = window_spread_json(c, w, mod, opt, warnings);
  j["moduli_volume_average"] = mod_vol.to_json();
  j["strength"] = s_punch.to_json();
  j["strength_volume_average"] = s_vol.to_json();

  // The paper's Fig. 7: every density reaches 42.3 MPa at 99 % of the theoretical density. The die's
  // walls do not move, so the box density is rho0 / (1 - strain) and 99 % TMD is reached at strain
  // 1 - rho0 / (0.99 TMD); the punch stress there is interpolated linearly between history rows.
  {
    constexpr double kFraction = 0.99;
    Json comp = Json::object();
    const double rho0 = number_or(spec, "density_kg_m3", std::nan("")),
                 tmd = number_or(spec, "tmd_kg_m3", std::nan(""));
    comp["tmd_fraction"] = kFraction;
    const double e99 = 1.0 - rho0 / (kFraction * tmd);
    Json value;
    std::string note;
    if (!(std::isfinite(e99) && e99 > 0.0)) {
      note = "no specimen density and TMD in run.json, or the specimen starts above 99 % TMD";
    } else {
      for (std::size_t i = 1; i < c.size(); ++i)
        if (c.strain[i - 1] <= e99 && c.strain[i] >= e99 && c.strain[i] > c.strain[i - 1]) {
          const double f = (e99 - c.strain[i - 1]) / (c.strain[i] - c.strain[i - 1]);
          value = Json(c.punch_stress[i - 1] + f * (c.punch_stress[i] - c.punch_stress[i - 1]));
          break;
        }
      if (value.is_null())
        note = fmt::format("the run ends at strain {:.4g}, before 99 % TMD at strain {:.4g}", c.strain.back(), e99);
    }
    comp["strain"] = std::isfinite(e99) ? Json(e99) : Json();
    comp["punch_stress_Pa"] = value;
    if (!note.empty()) comp["note"] = note;
    j["stress_at_99_tmd"] = comp;
  }

  Json agree = Json::object();
  agree["punch_vs_minus_syy"] = discrepancy_json(curve_discrepancy(c.strain, c.punch_stress, c.vol_axial, ramp));
  agree["wall_vs_minus_sxx"] = discrepancy_json(curve_discrepancy(c.strain, c.wall_stress, c.vol_lateral, ramp));
  agree["M_relative_difference"] = (mod.axial_vol.slope - mod.M) / mod.M;
  agree["lambda_relative_difference"] = (mod.lateral_vol.slope - mod.lambda) / mod.lambda;
  agree["strength_relative_difference"] = (s_vol.strength - s_punch.strength) / s_punch.strength;
  j["agreement"] = agree;
  const CurveDiscrepancy axial = curve_discrepancy(c.strain, c.punch_stress, c.vol_axial, ramp);
  if (axial.rms_relative > 0.05) {
    warnings.push_back(
        fmt::format("punch stress and volume-averaged -syy differ by {:.3g} % rms (of the maximum): "
                    "the punch reaction rings or the specimen is not in equilibrium",
                    100 * axial.rms_relative));
  }

  // KE/IE after the ramp (reported) and from the start of the linear window on (flagged): the
  // moduli and the strength are read there.
  double ke_ramp = 0, ke_max = 0, ke_whole_max = 0;
  int above = 0, n_after = 0, n_ramp = 0;
  for (std::size_t i = 0; i < c.size(); ++i) {
    if (c.strain[i] <= ramp || !std::isfinite(ke_ie[i])) continue;
    ++n_ramp;
    ke_ramp = std::max(ke_ramp, ke_ie[i]);
    if (c.strain[i] < w.lo) continue;
    ++n_after;
    ke_max = std::max(ke_max, ke_ie[i]);
    if (std::isfinite(c.ke_ie[i])) ke_whole_max = std::max(ke_whole_max, c.ke_ie[i]);
    if (ke_ie[i] > opt.ke_ie_limit) ++above;
  }
  Json qs = Json::object();
  qs["measure"] = beyond_affine
                      ? "kinetic energy beyond the affine motion behind the punch (KE - f m v^2/6) / stress work"
                      : "kinetic energy / stress work (the history's ke_ie)";
  qs["ke_ie_max_after_ramp"] = n_ramp ? Json(ke_ramp) : Json();
  qs["ke_ie_max_from_window_start"] = n_after ? Json(ke_max) : Json();
  qs["ke_ie_whole_max_from_window_start"] = n_after ? Json(ke_whole_max) : Json();  // with the affine motion
  qs["fraction_above_limit"] = n_after ? Json(double(above) / n_after) : Json();
  qs["limit"] = opt.ke_ie_limit;
  qs["flagged"] = ke_max > opt.ke_ie_limit;
  j["quasi_static"] = qs;
  if (ke_max > opt.ke_ie_limit) {
    warnings.push_back(fmt::format(
        "not quasi-static: KE/IE{} reaches {:.3g} after the start of the linear window at "
        "strain {:.4g} (limit {:.3g})",
        beyond_affine ? " (beyond the affine motion behind the punch)" : "", ke_max, w.lo, opt.ke_ie_limit));
  }
  j["energy_balance"] = energy_balance_json(c, std::max(w.lo, ramp), w.hi, opt, warnings);
  j["interpenetration"] = interpenetration_json(c, number_or(spec, "width_m", std::nan("")),
                                                number_or(spec, "height_m", std::nan("")), w.hi, opt, warnings);
  Json warn = Json::array();
  for (auto& s : warnings) warn.push_back(s);
  j["warnings"] = warn;
  j["curve"] = thinned_curve(c, opt.curve_points);
  return j;
}

Json analyze_run_to_file(const std::string& run_dir, const AnalysisOptions& opt) {
  Json j = analyze_run(run_dir, opt);
  json_write_file((fs::path(run_dir) / "analysis.json").string(), j);
  return j;
}

}  // namespace pbx
