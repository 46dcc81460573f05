// `pbxmpm material`: the material point driver (no grid). Reads one [materials.NAME] table of a
// deck, builds the 3D material at the requested temperature and drives it through a strain path,
// writing time, strain and the full stress with units in the column names.
#include <charconv>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <memory>
#include <string>

#include <CLI/CLI.hpp>
#include <fmt/format.h>
#include <fmt/ranges.h>

#include "app/commands.hpp"
#include "core/error.hpp"
#include "core/units.hpp"
#include "io/deck.hpp"
#include "materials/material.hpp"
#include "materials/point_driver.hpp"

namespace pbx::app {

namespace {

struct MaterialOptions {
  std::string deck, material, path, strain, rate, temperature, duration, out;
  int steps = 1000;
};

// A command-line quantity: a plain number is SI, a string may carry a unit ("250 1/s", "333 K").
double option_quantity(const std::string& text, const Dimension& d, const std::string& option) {
  double v = 0;
  const char* end = text.data() + text.size();
  auto [ptr, ec] = std::from_chars(text.data(), end, v);
  if (!(ec == std::errc() && ptr == end)) v = to_si(text, d, option);
  if (!std::isfinite(v)) throw InputError(fmt::format("{}: must be a finite number (got '{}')", option, text));
  return v;
}

void run_material(const MaterialOptions& o) {
  PointLoad load;
  load.path = parse_point_path(o.path);
  load.strain = option_quantity(o.strain, dim::none, "--strain");
  if (!o.rate.empty()) {
    load.rate = option_quantity(o.rate, dim::rate, "--rate");
    if (!(load.rate > 0.0)) throw InputError(fmt::format("--rate must be > 0 (got {} 1/s)", load.rate));
  }
  if (!o.duration.empty()) {
    load.duration = option_quantity(o.duration, dim::time, "--duration");
    if (!(load.duration > 0.0)) throw InputError(fmt::format("--duration must be > 0 (got {} s)", load.duration));
  }
  if (o.rate.empty() && o.duration.empty()) throw InputError("give --rate (1/s) or --duration (s)");
  if (!o.rate.empty() && !o.duration.empty())
    throw InputError(
        "give --rate or --duration, not both: the loading time (step_shear: the hold time) is "
        "|strain| / rate");
  load.steps = o.steps;
  const Deck deck = Deck::from_file(o.deck);
  const auto materials = deck.root().optional_table("materials");
  if (!materials) throw InputError(fmt::format("{}: no [materials] table in the deck", deck.name()));
  const auto table = materials->optional_table(o.material);
  if (!table)
    throw InputError(fmt::format("{}: no material '{}' in the deck (found: {})", deck.name(), o.material,
                                 fmt::join(materials->keys(), ", ")));
  // Without --temperature: the deck's run temperature, else the material's reference temperature
  // (where its constants hold), else 293 K; the banner below says which.
  double T = 293.0;
  const char* from = "default";
  const auto run = deck.root().optional_table("run");
  if (!o.temperature.empty()) {
    T = option_quantity(o.temperature, dim::temperature, "--temperature");
    from = "--temperature";
  } else if (run && run->has("temperature")) {
    T = run->quantity("temperature", dim::temperature, 293.0);
    from = "the deck's run.temperature";
  } else if (table->has("reference_temperature")) {
    // read from a second copy of the deck: reading marks a key used, and a model that takes no
    // reference_temperature must still have it reported as an unknown key by check_unused below
    const Deck peek = Deck::from_file(o.deck);
    T = peek.root().table("materials").table(o.material).quantity("reference_temperature", dim::temperature);
    from = "the material's reference_temperature";
  }
  if (!(T > 0.0)) throw InputError(fmt::format("--temperature must be > 0 K (got {})", T));
  MaterialContext ctx;
  ctx.temperature = T;
  ctx.name = o.material;
  const auto m = make_material<3>(*table, ctx);
  table->check_unused();  // a misspelt key of this material is an error here as in a run

  const auto samples = drive_point(*m, load);
  fmt::print(stderr,
             "pbxmpm material: '{}' ({}) at {} K ({}): rho0 = {:.6g} kg/m3, c_L = {:.6g} m/s; {} ({}), {} rows\n",
             o.material, m->model(), T, from, m->density(), m->initial_wave_speed(), point_path_name(load.path),
             point_strain_meaning(load.path), samples.size());
  if (o.out.empty() || o.out == "-") {
    write_point_csv(std::cout, samples);
  } else {
    std::ofstream f(o.out);
    if (!f) throw InputError(fmt::format("--out: cannot write '{}'", o.out));
    write_point_csv(f, samples);
  }
}

}  // namespace

void register_material(CLI::App& app) {
  auto o = std::make_shared<MaterialOptions>();
  auto* c = app.add_subcommand("material", "drive one material point (no grid) through a strain path");
  c->add_option("deck", o->deck, "deck holding a [materials.NAME] table")->required();
  c->add_option("--material", o->material, "name of the material table")->required();
  c->add_option("--path", o->path, "uniaxial_strain | uniaxial_stress | simple_shear | step_shear | hydrostatic")
      ->required();
  c->add_option("--strain", o->strain,
                "target strain, tension positive (axial ln F_xx, shear F_xy, or volumetric ln J)")
      ->required();
  c->add_option("--rate", o->rate, "strain rate magnitude, 1/s (number or quantity such as '250 1/s')");
  c->add_option("--temperature", o->temperature,
                "temperature (a plain number is K; default: the deck's run.temperature, else the material's "
                "reference_temperature, else 293 K)");
  c->add_option("--duration", o->duration, "loading time (default |strain|/rate); step_shear: hold time, s");
  c->add_option("--steps", o->steps, "number of steps / output times (default 1000)")->check(CLI::Range(1, 10000000));
  c->add_option("--out", o->out, "CSV output file (default: standard output)");
  c->callback([o] { run_material(*o); });
}

}  // namespace pbx::app
