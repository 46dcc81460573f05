#include "contact/binder_layer.hpp"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "core/error.hpp"
#include "core/units.hpp"
#include "core/param_table.hpp"
#include "materials/point_driver.hpp"

namespace pbx {

namespace {
constexpr Dimension kStiffnessPerArea{{-2, 1, -2, 0, 0}};  // Pa/m
// Small enough that the Tait EOS stays linear (K changes by ~1e-4 relative), large enough for
// round-off: the secant is sigma / strain.
constexpr double kProbeStrain = 1e-4;
constexpr int kProbeSteps = 400;
}  // namespace

void LayerLaw::at_time(double t) {
  if (time.size() == 1 || t <= time.front()) {
    kn = normal.front(), kt = shear.front();
    return;
  }
  if (t >= time.back()) {
    kn = normal.back(), kt = shear.back();
    return;
  }
  const auto hi = static_cast<std::size_t>(std::upper_bound(time.begin(), time.end(), t) - time.begin());
  const std::size_t lo = hi - 1;
  const double s = (t - time[lo]) / (time[hi] - time[lo]);
  kn = normal[lo] + s * (normal[hi] - normal[lo]);
  kt = shear[lo] + s * (shear[hi] - shear[lo]);
}

LayerLaw read_layer_law(const ParamTable& t) {
  LayerLaw law;
  law.friction = t.number("friction");
  if (!(law.friction >= 0.0))
    t.fail("friction", fmt::format("friction coefficient must be >= 0, got {}", law.friction));
  std::string gap_word;
  try {
    if (t.has("bond_gap")) gap_word = t.string("bond_gap");
  } catch (const InputError&) {  // a plain number: metres
  }
  if (gap_word == "thickness")
    law.bond_within_thickness = true;
  else
    law.bond_gap = t.non_negative("bond_gap", dim::length, 0.0);
  if (t.has("bond_depth")) law.bond_depth = t.positive("bond_depth", dim::length);
  if (t.has("film")) {
    const std::string film = t.string("film");
    if (film != "uniform" && film != "integrated" && film != "bonds")
      t.fail("film", fmt::format("must be 'uniform', 'integrated' or 'bonds', got '{}'", film));
    law.integrated = film == "integrated" || film == "bonds";
    law.bonds = film == "bonds";
  }
  law.join_gap_binder = law.bonds;
  if (t.has("gap_binder")) {
    const std::string gap = t.string("gap_binder");
    if (gap != "join" && gap != "free") t.fail("gap_binder", fmt::format("must be 'join' or 'free', got '{}'", gap));
    if (!law.integrated)
      t.fail("gap_binder", "applies only with film = \"integrated\" or \"bonds\" (the gaps are those of its film)");
    law.join_gap_binder = gap == "join";
  }
  if (law.integrated && t.has("bond_gap"))
    t.fail("bond_gap",
           "does not apply with film = \"integrated\": its springs act on the band of one cell that the grid lets "
           "two bodies share, and its film reaches film_extent x t");
  if (t.has("film_extent")) {
    if (!law.integrated) t.fail("film_extent", "applies only with film = \"integrated\" or \"bonds\"");
    law.film_extent = t.number("film_extent");
    if (!(law.film_extent >= 0.0 && law.film_extent <= 100.0))
      t.fail("film_extent",
             fmt::format("must lie in [0, 100] (a multiple of the layer thickness), got {}", law.film_extent));
  }
  if (t.has("shear_cap")) {
    const std::string cap = t.string("shear_cap");
    if (cap != "coulomb" && cap != "none")
      t.fail("shear_cap", fmt::format("must be 'coulomb' or 'none', got '{}'", cap));
    law.shear_cap = cap == "coulomb";
  }
  if (t.has("flow_stress") && t.has("flow_factor"))
    t.fail("flow_factor", "give either flow_stress or flow_factor, not both");
  if (t.has("flow_stress")) law.flow_stress = t.positive("flow_stress", dim::pressure);
  if (t.has("flow_factor")) {
    law.flow_factor = t.number("flow_factor");
    if (!(law.flow_factor > 0.0 && std::isfinite(law.flow_factor)))
      t.fail("flow_factor",
             fmt::format("must be > 0 (the film's flow pressure over the binder's secant shear modulus), got {}",
                         law.flow_factor));
  }
  const bool direct = t.has("normal_stiffness") || t.has("shear_stiffness");
  if (direct) {
    for (const char* k :
         {"binder", "thickness", "coat_scale", "load_time", "closure", "film", "film_extent", "gap_binder"})
      if (t.has(k)) t.fail(k, "give either normal_stiffness and shear_stiffness, or binder and thickness, not both");
    if (law.bond_within_thickness)
      t.fail("bond_gap", "\"thickness\" needs a layer thickness: give binder and thickness");
    if (law.flow_factor > 0.0)
      t.fail("flow_factor", "needs the binder's shear modulus: give binder and thickness (or flow_stress)");
    law.time = {0.0};
    law.normal = {t.positive("normal_stiffness", kStiffnessPerArea)};
    law.shear = {t.non_negative("shear_stiffness", kStiffnessPerArea)};
    return law;
  }
  law.binder = t.string("binder");
  std::string how;
  try {
    how = t.string("thickness");
  } catch (const InputError&) {  // a length with its unit, or a plain number in metres
  }
  if (how == "coats") {
    law.from_coats = true;
    law.coat_scale = t.number("coat_scale", 1.0);
    if (!(law.coat_scale > 0.0 && std::isfinite(law.coat_scale)))
      t.fail("coat_scale", fmt::format("must be > 0, got {}", law.coat_scale));
  } else {
    if (t.has("coat_scale")) t.fail("coat_scale", "applies only with thickness = \"coats\"");
    law.thickness = t.positive("thickness", dim::length);
  }
  law.closure = t.number("closure", 1.0);
  if (!(law.closure > 0.0 && law.closure <= 1.0))
    t.fail("closure", fmt::format("must lie in (0, 1], got {}", law.closure));
  if (t.has("load_time")) {
    std::string word;
    try {
      word = t.string("load_time");
    } catch (const InputError&) {  // a plain number: seconds
    }
    if (word != "elapsed") law.load_time = t.positive("load_time", dim::time);
  }
  if (law.bonds) {
    // what the pair springs do not have yet (docs/theory/contact.md, "Films on particle pairs")
    if (law.flows())
      t.fail(law.flow_stress > 0.0 ? "flow_stress" : "flow_factor", "film flow is not built for film = \"bonds\"");
  }
  return law;
}

void layer_moduli(LayerLaw& law, const Material<3>& binder, double end_time, const ParamTable& where) {
  if (law.binder.empty()) return;
  const bool elapsed = law.load_time == 0.0;
  // past the run's end time, so the table covers every step (the last one may overshoot)
  const double horizon = elapsed ? 1.2 * end_time : law.load_time;
  if (!(horizon > 0.0)) where.fail("load_time", "the run has no duration to take the binder's moduli over");
  PointLoad load;
  load.strain = -kProbeStrain;  // compression, where the layer works
  load.rate = kProbeStrain / horizon;
  load.steps = kProbeSteps;
  load.path = PointPath::uniaxial_strain;
  const std::vector<PointSample> axial = drive_point(binder, load);
  load.strain = kProbeStrain;
  load.path = PointPath::simple_shear;
  const std::vector<PointSample> shear = drive_point(binder, load);
  law.time.clear(), law.normal.clear(), law.shear.clear();
  for (std::size_t k = 1; k < axial.size(); ++k) {
    const double M = axial[k].stress.xx / axial[k].strain, G = shear[k].stress.xy / shear[k].strain;
    if (!(M > 0.0 && G >= 0.0 && std::isfinite(M) && std::isfinite(G)))
      where.fail("binder", fmt::format("material '{}' gives no usable layer moduli at t = {:.4g} s (M = {:.4g} Pa, "
                                       "G = {:.4g} Pa)",
                                       law.binder, axial[k].time, M, G));
    // the first sample stands for t -> 0 (the instantaneous moduli, to within one probe step)
    law.time.push_back(k == 1 ? 0.0 : axial[k].time);
    law.normal.push_back(M);
    law.shear.push_back(G);
  }
  if (!elapsed) {  // one value: the secant over the fixed load time
    law.time = {0.0};
    law.normal = {law.normal.back()};
    law.shear = {law.shear.back()};
  }
  law.at_time(0.0);
}

}  // namespace pbx
