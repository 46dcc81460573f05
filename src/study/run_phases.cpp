#include "study/run_phases.hpp"

#include <filesystem>
#include <utility>
#include <fmt/format.h>

#include "core/error.hpp"
#include "core/units.hpp"
#include "io/deck.hpp"
#include "materials/point_driver.hpp"
#include "bodies/die.hpp"

namespace pbx {
namespace {

namespace fs = std::filesystem;

const Json& member(const Json& j, const std::string& key, const std::string& file) {
  const Json* v = json_find(j, key);
  if (!v) throw InputError(fmt::format("{}: no \"{}\"", file, key));
  return *v;
}

// Stress of one material point after a step of strain (L dt over a 1 fs jump) held for t_hold.
Sym3 held_step_stress(const Material<3>& m, const Mat3& strain, double t_hold) {
  constexpr double t_jump = 1e-15;  // short against any relaxation time (see drive_point's step_shear)
  MaterialPoint<3> mp(m);
  mp.step(strain / t_jump, t_jump);
  if (t_hold > 0) mp.step(Mat3::Zero(), t_hold);
  return mp.stress();
}

}  // namespace

RunPhases run_phases(const StudyRun& run) {
  const fs::path dir(run.dir);
  const std::string rj_file = (dir / "run.json").string();
  const Json rj = json_read_file(rj_file);
  RunPhases out;
  out.temperature_K = json_number(member(rj, "temperature_K", rj_file), rj_file + ": temperature_K");
  const Json& spec = member(rj, "specimen", rj_file);
  if (!spec.is_object()) throw InputError(fmt::format("{}: \"specimen\" is null (the run has no die)", rj_file));
  const double porosity = json_number(member(spec, "porosity", rj_file), rj_file + ": specimen.porosity");

  const Json* window = json_find(run.analysis, "linear_window");
  const double lo =
      window && json_find(*window, "lo") ? json_number(*json_find(*window, "lo"), "linear_window.lo") : NAN;
  const double hi =
      window && json_find(*window, "hi") ? json_number(*json_find(*window, "hi"), "linear_window.hi") : NAN;
  if (!(std::isfinite(lo) && std::isfinite(hi)))
    throw InputError(fmt::format("{}/analysis.json: no linear window (linear_window.lo/hi)", run.dir));

  const Deck deck = Deck::from_file((dir / "deck.toml").string());
  // The punch timing as the run had it: run.json records the ramp, the speed (since 2026-12-06) and
  // the height; a run.json without them is read from the deck with the scene's own default ramp
  // (this used to take 0 where the scene takes 0.002, so the phases of a deck without ramp_strain
  // were evaluated at a loading time short by 0.2 % of strain).
  const DeckTable die = deck.root().table("die");
  const Json* rj_ramp = json_find(rj, "ramp_strain");
  const Json* rj_v = json_find(rj, "punch_velocity_m_s");
  const Json* rj_h = json_find(spec, "height_m");
  Die fixture;
  fixture.height = rj_h && rj_h->is_number() ? json_number(*rj_h) : die.positive("height", dim::length);
  fixture.punch_velocity =
      rj_v && rj_v->is_number() ? json_number(*rj_v) : die.positive("punch_velocity", dim::velocity);
  fixture.ramp_strain =
      rj_ramp && rj_ramp->is_number() ? json_number(*rj_ramp) : die.number("ramp_strain", kDefaultRampStrain);
  out.load_time_s = fixture.time_at_strain(0.5 * (lo + hi));

  const DeckTable materials = deck.root().table("materials");
  const Json& mats = member(rj, "materials", rj_file);
  double particles = 0;
  for (const Json& m : json_array(mats))
    particles += json_number(member(m, "particles", rj_file), rj_file + ": materials.particles");
  if (!(particles > 0)) throw InputError(fmt::format("{}: the materials hold no particles", rj_file));
  for (const Json& m : json_array(mats)) {
    const std::string name = json_string(member(m, "name", rj_file), rj_file + ": materials.name");
    const double n = json_number(member(m, "particles", rj_file));
    const auto table = materials.optional_table(name);
    if (!table)
      throw InputError(
          fmt::format("{}: run.json names material '{}', which the deck does not hold", deck.name(), name));
    MaterialContext ctx;
    ctx.temperature = out.temperature_K;
    ctx.name = name;
    const auto law = make_material<3>(*table, ctx);
    constexpr double e = 1e-6;  // small against any yield strain, large against round-off
    const Sym3 sv = held_step_stress(*law, Mat3::Identity() * (-e / 3.0), out.load_time_s);
    Mat3 shear = Mat3::Zero();
    shear(0, 1) = e;
    const Sym3 ss = held_step_stress(*law, shear, out.load_time_s);
    // ln J = -e: K = mean stress / ln J; engineering shear e: G = sigma_xy / e (to O(e)).
    out.phases.push_back({sv.mean() / -e, ss.xy / e, (1.0 - porosity) * n / particles, name});
  }
  if (porosity > 0) out.phases.push_back({0, 0, porosity, "pores"});
  return out;
}

std::vector<Phase> run_phases_for_bounds(const StudyRun& run, std::string& source) {
  RunPhases rp = run_phases(run);
  std::string list;
  for (const auto& p : rp.phases) {
    list += fmt::format("{}{} K {:.4g} GPa, G {:.4g} GPa, f {:.4f}", list.empty() ? "" : "; ", p.name,
                        p.bulk_modulus / 1e9, p.shear_modulus / 1e9, p.volume_fraction);
  }
  source = fmt::format(
      "the run's materials at {:g} K after a hold of {:.3g} s (the loading time to the middle of the "
      "linear window): {}",
      rp.temperature_K, rp.load_time_s, list);
  return std::move(rp.phases);
}

}  // namespace pbx
