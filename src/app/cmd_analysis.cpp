// pbxmpm analyze / fit / report: the analysis of run and study directories (src/analysis).
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <sstream>
#include <string>

#include <CLI/CLI.hpp>
#include <fmt/format.h>
#include <toml++/toml.h>

#include "analysis/csv_table.hpp"
#include "analysis/density_law.hpp"
#include "analysis/normalized_curve_law.hpp"
#include "analysis/run_analysis.hpp"
#include "analysis/study_fits.hpp"
#include "analysis/study_report.hpp"
#include "analysis/temperature_law.hpp"
#include "app/commands.hpp"
#include "core/error.hpp"
#include "core/parse_number.hpp"
#include "core/units.hpp"
#include "io/deck.hpp"
#include "io/json.hpp"
#include "study/run_phases.hpp"

namespace pbx::app {

namespace {

// "lo:hi" -> two numbers, or InputError naming the option.
std::pair<double, double> range_option(const std::string& text, const std::string& option) {
  const auto colon = text.find(':');
  if (colon == std::string::npos) throw InputError(fmt::format("{}: expected LO:HI, got '{}'", option, text));
  auto whole = [&](const std::string& part) {
    const auto v = parse_finite(part);
    if (!v) throw InputError(fmt::format("{}: expected two finite numbers LO:HI, got '{}'", option, text));
    return *v;
  };
  return {whole(text.substr(0, colon)), whole(text.substr(colon + 1))};
}

// A quantity given on the command line, which must be finite and > 0.
double quantity_option(const std::string& text, const Dimension& d, const std::string& option) {
  // a plain number is in SI units, as in the decks ("293" is 293 K)
  const auto plain = parse_finite(text);
  const double v = plain ? *plain : to_si(text, d, option);
  if (!(v > 0) || !std::isfinite(v))
    throw InputError(fmt::format("{}: must be a finite quantity > 0 (got '{}')", option, text));
  return v;
}

// A plain number option, or InputError naming the option: flags must never be ignored silently.
double number_option(const std::string& text, const std::string& option, double lo, bool lo_open) {
  const auto v = parse_finite(text);
  if (!v || (lo_open ? !(*v > lo) : !(*v >= lo)))
    throw InputError(
        fmt::format("{}: expected a finite number {} {} (got '{}')", option, lo_open ? ">" : ">=", lo, text));
  return *v;
}

void check_confidence(double c) {
  if (!(c > 0 && c < 1)) throw InputError(fmt::format("--confidence: must lie in (0, 1), e.g. 0.95 (got {})", c));
}

// SI factor of a column from its name's unit suffix, which must be one of `dimension`'s: a column
// of stresses, moduli, densities or temperatures without a stated unit is refused, not read as SI.
double unit_factor(const std::string& column, const Dimension& dimension, const std::string& option) {
  const double f = column_unit_factor(column);
  auto ends = [&](const char* suffix) {
    const std::string s(suffix);
    return column.size() >= s.size() && column.compare(column.size() - s.size(), s.size(), s) == 0;
  };
  bool stated = false;
  const char* expected = "";
  if (dimension == dim::pressure) {
    stated = ends("_Pa") || ends("_kPa") || ends("_MPa") || ends("_GPa");
    expected = "_Pa, _kPa, _MPa or _GPa";
  } else if (dimension == dim::density) {
    stated = ends("_kg_m3") || ends("_g_cm3");
    expected = "_kg_m3 or _g_cm3";
  } else if (dimension == dim::temperature) {
    stated = ends("_K");
    expected = "_K (kelvin)";
  } else {
    return f;  // strain: a fraction, or percent with _percent
  }
  if (!stated)
    throw InputError(fmt::format("{} '{}': the column name must end with its unit, {} (e.g. rename the column)", option,
                                 column, expected));
  return f;
}

void print_fit(const FitResult& f) {
  fmt::print("{}\n  method: {}\n", f.model, f.method);
  for (const auto& p : f.params) {
    if (std::isfinite(p.ci_low) && std::isfinite(p.ci_high))
      fmt::print("  {:>8} = {:.6g} {}  ({:.0f} % CI [{:.6g}, {:.6g}], SE {:.3g})\n", p.name, p.value, p.unit,
                 100 * f.confidence, p.ci_low, p.ci_high, p.std_error);
    else
      fmt::print("  {:>8} = {:.6g} {}  (no confidence interval: see the note)\n", p.name, p.value, p.unit);
  }
  fmt::print("  n = {}, dof = {}, SSE = {:.6g}, R^2 = {:.6f}{}\n", f.n, f.dof, f.sse, f.r2,
             f.note.empty() ? "" : "\n  note: " + f.note);
}

std::vector<double> scaled_column(const CsvTable& t, const std::string& name, const Dimension& d,
                                  const std::string& option) {
  std::vector<double> v = t.numbers(name);
  const double s = unit_factor(name, d, option);
  for (std::size_t r = 0; r < v.size(); ++r) {
    const double raw = v[r];
    v[r] *= s;
    // 1e303 MPa is finite as written and infinite in Pa: refused here, not fitted into NaN
    if (!std::isfinite(v[r]))
      throw InputError(fmt::format("column '{}', data row {}: {:g} overflows when converted to SI units (x {:g})", name,
                                   r + 1, raw, s));
  }
  return v;
}

struct AnalyzeArgs {
  std::string dir, window, plateau, options_file, window_signal;
  std::string strength_strain, tolerance, ke_ie;  // "" = not given
  bool allow_unfinished = false;
  std::string options_text, options_source;  // an [analysis] table given as text (the run's own deck's)
};

AnalysisOptions analysis_options(const AnalyzeArgs& a) {
  AnalysisOptions o;
  if (!a.options_file.empty() || !a.options_text.empty()) {
    Deck deck =
        a.options_file.empty() ? Deck::from_string(a.options_text, a.options_source) : Deck::from_file(a.options_file);
    if (auto t = deck.root().optional_table("analysis")) o = AnalysisOptions::from_deck(*t);
    deck.check_unused();
  }
  if (!a.window.empty()) {
    auto [lo, hi] = range_option(a.window, "--window");
    o.window_lo = lo;
    o.window_hi = hi;
  }
  if (!a.plateau.empty()) {
    auto [lo, hi] = range_option(a.plateau, "--plateau");
    o.plateau_lo = lo;
    o.plateau_hi = hi;
  }
  if (!a.strength_strain.empty())
    o.strength_max_strain = number_option(a.strength_strain, "--strength-strain", 0, true);
  if (!a.tolerance.empty()) o.window_tolerance = number_option(a.tolerance, "--window-tolerance", 0, true);
  if (!a.window_signal.empty()) o.window_signal = a.window_signal;
  if (!a.ke_ie.empty()) o.ke_ie_limit = number_option(a.ke_ie, "--ke-ie-limit", 0, false);
  o.allow_unfinished = a.allow_unfinished;
  o.validate();
  return o;
}

// run.json keeps the deck as JSON (toml++'s JSON form of it); its [analysis] table back as TOML:
// numbers, strings, booleans and arrays of them, as the table's keys take.
toml::array toml_array_of(const Json& j);
toml::table analysis_table_of(const Json& j) {
  toml::table t;
  for (const auto& [key, v] : j.items()) {
    if (v.is_number_integer())
      t.insert(key, v.get<std::int64_t>());
    else if (v.is_number())
      t.insert(key, v.get<double>());
    else if (v.is_string())
      t.insert(key, v.get<std::string>());
    else if (v.is_boolean())
      t.insert(key, v.get<bool>());
    else if (v.is_array())
      t.insert(key, toml_array_of(v));
    else
      throw InputError(fmt::format("run.json: deck.analysis.{}: not a value an [analysis] key takes", key));
  }
  return t;
}
toml::array toml_array_of(const Json& j) {
  toml::array a;
  for (const auto& v : j) {
    if (v.is_number_integer())
      a.push_back(v.get<std::int64_t>());
    else if (v.is_number())
      a.push_back(v.get<double>());
    else if (v.is_string())
      a.push_back(v.get<std::string>());
    else
      throw InputError("run.json: deck.analysis: an array entry that is not a number or a string");
  }
  return a;
}
std::string analysis_table_as_toml(const Json& j) {
  std::stringstream ss;
  ss << toml::table{{"analysis", analysis_table_of(j)}} << "\n";
  return ss.str();
}

// A study directory's analysis.toml (its deck's [analysis] table) is the default options file of
// `fit study` and `report`, so they read the runs the way the study did.
// quiet: the options are not used to analyse (report --reuse-analysis), so no line says they are.
AnalyzeArgs with_study_options(AnalyzeArgs a, bool quiet = false) {
  const std::string file = a.dir + "/analysis.toml";
  if (a.options_file.empty() && std::filesystem::exists(file)) {
    a.options_file = file;
    if (!quiet) fmt::print(stderr, "pbxmpm: analysis options from {} (the study deck's [analysis] table)\n", file);
  }
  return a;
}

// A run of a study (STUDY/runs/<id>) is analysed by `analyze` with the study's analysis.toml too,
// as the study and its report analysed it; the line on stderr says so (--options overrides).
// Otherwise a run whose deck carried an [analysis] table (a study writes its own into every run
// deck, so a deck taken out of a study keeps it) is analysed with that table, which run.json keeps
// with the rest of the deck: run alone, the deck's run is read as its study read it.
AnalyzeArgs with_run_study_options(AnalyzeArgs a) {
  std::filesystem::path run = std::filesystem::absolute(a.dir).lexically_normal();
  if (!run.has_filename()) run = run.parent_path();  // "runs/ID/" or "." from inside the run
  const std::filesystem::path study = run.parent_path().parent_path();
  if (a.options_file.empty() && run.parent_path().filename() == "runs" &&
      std::filesystem::exists(study / "study.json") && std::filesystem::exists(study / "analysis.toml")) {
    a.options_file = (study / "analysis.toml").string();
    fmt::print(stderr, "pbxmpm: analysis options from {} (the study's [analysis] table; --options to use others)\n",
               a.options_file);
  } else if (a.options_file.empty() && std::filesystem::exists(run / "run.json")) {
    const Json record = json_read_file((run / "run.json").string());
    const Json* deck = json_find(record, "deck");
    const Json* table = deck ? json_find(*deck, "analysis") : nullptr;
    if (table && table->is_object()) {
      a.options_text = analysis_table_as_toml(*table);
      a.options_source = (run / "run.json").string() + " (the run deck's [analysis] table)";
      fmt::print(stderr,
                 "pbxmpm: analysis options from the run deck's [analysis] table (in {}; --options to use "
                 "others)\n",
                 (run / "run.json").string());
    }
  }
  return a;
}

void add_analysis_flags(CLI::App* c, AnalyzeArgs& a) {
  c->add_option("--window", a.window, "linear window LO:HI in strain (default: found automatically)");
  c->add_option("--plateau", a.plateau, "plateau window LO:HI in strain for the yield intersection");
  c->add_option("--strength-strain", a.strength_strain,
                "end of the strength window: compression strength = mean stress from strength_plateau_from (0.005) to "
                "this strain, the peak reported beside it (default 0.03)");
  c->add_option("--window-signal", a.window_signal,
                "curve for the automatic window: volume_average (default) or punch");
  c->add_option("--window-tolerance", a.tolerance, "automatic window: allowed drop of the end tangent (default 0.10)");
  c->add_option("--ke-ie-limit", a.ke_ie,
                "flag runs whose KE/IE exceeds this from the linear window's start; the automatic window starts where "
                "KE/IE has settled below it (default 0.05)");
  c->add_option("--options", a.options_file, "TOML file with an [analysis] table (docs/deck/analysis.md)");
  c->add_flag("--allow-unfinished", a.allow_unfinished, "analyse runs whose run.json status is not 'finished'");
}

struct StudyArgs {
  std::string T0, eq14_window, GU, KU, rho0;
  double confidence = 0.95;
  bool partial = false;
};

void add_study_flags(CLI::App* c, StudyArgs& a) {
  c->add_flag("--partial", a.partial,
              "use the finished runs of an incomplete study (the others are named in fits.json and the report)");
  c->add_option("--T0", a.T0, "reference temperature of Eq. 13/14 (default 293 K)");
  c->add_option("--eq14-window", a.eq14_window, "Eq. 14 fitting window LO:HI in percent strain (default 0.5:3)");
  c->add_option("--GU", a.GU, "upper-bound shear modulus G^U of Eq. 21 (default 10.84 GPa)");
  c->add_option("--KU", a.KU, "upper-bound bulk modulus K^U of Eq. 22 (default 10.52 GPa)");
  c->add_option("--rho0", a.rho0, "theoretical maximum density (default: the runs' tmd_kg_m3, else 1942 kg/m3)");
  c->add_option("--confidence", a.confidence, "confidence level of the intervals (default 0.95)");
}

void apply_study_flags(const StudyArgs& a, StudyFitOptions& o) {
  if (!a.T0.empty()) o.T0_K = quantity_option(a.T0, dim::temperature, "--T0");
  if (!a.eq14_window.empty()) {
    auto [lo, hi] = range_option(a.eq14_window, "--eq14-window");
    if (!(hi > lo && lo > 0)) throw InputError("--eq14-window: needs 0 < LO < HI (percent strain)");
    o.eq14_lo_percent = lo;
    o.eq14_hi_percent = hi;
  }
  if (!a.GU.empty()) o.GU = quantity_option(a.GU, dim::pressure, "--GU");
  if (!a.KU.empty()) o.KU = quantity_option(a.KU, dim::pressure, "--KU");
  if (!a.rho0.empty()) o.rho0 = quantity_option(a.rho0, dim::density, "--rho0");
  check_confidence(a.confidence);
  o.confidence = a.confidence;
  o.partial = a.partial;
  o.run_phases = run_phases_for_bounds;
}

}  // namespace

void register_analysis(CLI::App& app) {
  // ---- analyze ----
  auto aa = std::make_shared<AnalyzeArgs>();
  auto* an = app.add_subcommand("analyze", "analyse a run directory (history.csv, run.json) into analysis.json");
  an->add_option("RUN_DIR", aa->dir, "run directory")->required();
  add_analysis_flags(an, *aa);
  an->callback([aa] {
    const Json j = analyze_run_to_file(aa->dir, analysis_options(with_run_study_options(*aa)));
    auto n = [&](std::initializer_list<const char*> path) {
      const Json* p = &j;
      for (auto k : path) p = p ? json_find(*p, k) : nullptr;
      return p && p->is_number() ? json_number(*p) : std::nan("");
    };
    fmt::print("linear window: strain {:.4g} .. {:.4g} ({} points)\n", n({"linear_window", "lo"}),
               n({"linear_window", "hi"}), n({"linear_window", "points"}));
    fmt::print("M = {:.4g} GPa, lambda = {:.4g} GPa, K = {:.4g} GPa, G = {:.4g} GPa, E = {:.4g} GPa, nu = {:.4f}\n",
               n({"moduli", "M_Pa"}) / 1e9, n({"moduli", "lambda_Pa"}) / 1e9, n({"moduli", "K_Pa"}) / 1e9,
               n({"moduli", "G_Pa"}) / 1e9, n({"moduli", "E_Pa"}) / 1e9, n({"moduli", "nu"}));
    fmt::print("from volume averages: M = {:.4g} GPa, K = {:.4g} GPa, G = {:.4g} GPa, E = {:.4g} GPa\n",
               n({"moduli_volume_average", "M_Pa"}) / 1e9, n({"moduli_volume_average", "K_Pa"}) / 1e9,
               n({"moduli_volume_average", "G_Pa"}) / 1e9, n({"moduli_volume_average", "E_Pa"}) / 1e9);
    fmt::print(
        "strength (plateau mean) = {:.4g} MPa, peak {:.4g} MPa at strain {:.4g}; yield = {:.4g} MPa at strain {:.4g}\n",
        n({"strength", "strength_Pa"}) / 1e6, n({"strength", "peak_strength_Pa"}) / 1e6,
        n({"strength", "strain_at_peak"}), n({"strength", "yield_stress_Pa"}) / 1e6, n({"strength", "yield_strain"}));
    fmt::print("punch vs volume-average stress: rms difference {:.3g} % of max\n",
               100 * n({"agreement", "punch_vs_minus_syy", "rms_relative"}));
    for (const auto& w : json_array(*json_find(j, "warnings"))) fmt::print("warning: {}\n", json_string(w));
    fmt::print("wrote {}/analysis.json\n", aa->dir);
  });

  // ---- fit ----
  auto* fit = app.add_subcommand("fit", "fit the paper's constitutive equations to a CSV file or a study");
  fit->require_subcommand(1);

  struct FitArgs {
    std::string csv, out, x, y, y2, window = "0.5:3", T0 = "293 K", rho0 = "1942 kg/m3", GU = "10.84 GPa",
                                    KU = "10.52 GPa", strength;
    double confidence = 0.95;
  };
  // One argument set per sub-command: CLI11 writes default values into the bound variables.
  auto write_out = [](const std::string& out, const Json& j) {
    if (out.empty()) return;
    json_write_file(out, j);
    fmt::print("wrote {}\n", out);
  };

  auto ta = std::make_shared<FitArgs>();
  auto* ft = fit->add_subcommand("temperature", "Eq. 13, sigma_c = sigma0 exp(alpha (1 - T/T0)), both methods");
  ft->add_option("CSV", ta->csv, "CSV file with a header line")->required();
  ft->add_option("--T-col", ta->x, "temperature column (K)")->default_val("T_K");
  ft->add_option("--strength-col", ta->y, "strength column; unit from its suffix (_Pa, _MPa, _GPa)")
      ->default_val("strength_MPa");
  ft->add_option("--T0", ta->T0, "reference temperature")->default_val("293 K");
  ft->add_option("--confidence", ta->confidence, "confidence level of the intervals")->default_val(0.95);
  ft->add_option("--out", ta->out, "write the fits as JSON");
  ft->callback([ta, write_out] {
    check_confidence(ta->confidence);
    const CsvTable t = CsvTable::read(ta->csv);
    const auto T = scaled_column(t, ta->x, dim::temperature, "--T-col");
    const auto s = scaled_column(t, ta->y, dim::pressure, "--strength-col");
    const double T0 = quantity_option(ta->T0, dim::temperature, "--T0");
    const FitResult nl = fit_temperature_law_nonlinear(T, s, T0, ta->confidence);
    const FitResult ll = fit_temperature_law_loglinear(T, s, T0, ta->confidence);
    print_fit(nl);
    print_fit(ll);
    Json j = Json::object();
    j["nonlinear"] = nl.to_json();
    j["loglinear"] = ll.to_json();
    write_out(ta->out, j);
  });

  auto ca = std::make_shared<FitArgs>();
  auto* fc = fit->add_subcommand("curve", "Eq. 14, sigma_n = A e + B e^n (e in percent), on the plateau window");
  fc->add_option("CSV", ca->csv, "CSV file with a header line (e.g. a history.csv)")->required();
  fc->add_option("--strain-col", ca->x, "strain column (fraction; '_percent' suffix for percent)")
      ->default_val("strain");
  fc->add_option("--stress-col", ca->y, "stress column, compression positive; unit from its suffix")
      ->default_val("punch_stress_Pa");
  fc->add_option("--strength", ca->strength,
                 "sigma_c used to normalise (e.g. '32.8 MPa'); default: max stress in the window");
  fc->add_option("--window", ca->window, "fitting window LO:HI in percent strain")->default_val("0.5:3");
  fc->add_option("--confidence", ca->confidence, "confidence level of the intervals")->default_val(0.95);
  fc->add_option("--out", ca->out, "write the fit as JSON");
  fc->callback([ca, write_out] {
    check_confidence(ca->confidence);
    const CsvTable t = CsvTable::read(ca->csv);
    const auto e = scaled_column(t, ca->x, dim::none, "--strain-col");
    const auto s = scaled_column(t, ca->y, dim::pressure, "--stress-col");
    auto [lo, hi] = range_option(ca->window, "--window");
    if (!(std::isfinite(lo) && std::isfinite(hi) && hi > lo && lo >= 0))
      throw InputError(fmt::format("--window: needs 0 <= LO < HI in percent strain (got '{}')", ca->window));
    std::vector<double> ep, sp;
    for (std::size_t i = 0; i < e.size(); ++i) {
      if (100 * e[i] >= lo && 100 * e[i] <= hi) {
        ep.push_back(100 * e[i]);
        sp.push_back(s[i]);
      }
    }
    if (ep.empty()) {
      const auto [mn, mx] = std::minmax_element(e.begin(), e.end());
      throw InputError(
          fmt::format("{}: no row has '{}' in the window {} .. {} % strain (the file spans {:.4g} .. {:.4g} %; "
                      "a column in percent must be named *_percent)",
                      ca->csv, ca->x, lo, hi, e.empty() ? 0.0 : 100 * *mn, e.empty() ? 0.0 : 100 * *mx));
    }
    double sc = 0;
    if (!ca->strength.empty()) {
      sc = quantity_option(ca->strength, dim::pressure, "--strength");
    } else {
      for (double x : sp) sc = std::max(sc, x);
    }
    if (!(sc > 0))
      throw InputError(
          fmt::format("{}: the largest '{}' in the window is {:.4g} Pa; Eq. 14 needs compression positive "
                      "(or give --strength)",
                      ca->csv, ca->y, sc));
    for (auto& x : sp) x /= sc;
    const FitResult f = fit_normalized_curve(ep, sp, ca->confidence);
    fmt::print("normalised by sigma_c = {:.6g} Pa; window {} .. {} % strain\n", sc, lo, hi);
    print_fit(f);
    Json j = f.to_json();
    j["sigma_c_Pa"] = sc;
    j["window_percent"] = json_numbers({lo, hi});
    write_out(ca->out, j);
  });

  auto da = std::make_shared<FitArgs>();
  auto* fd = fit->add_subcommand("density", "Eq. 19-22, M/M^U = k (rho/rho0)^n for G and K");
  fd->add_option("CSV", da->csv, "CSV file with a header line")->required();
  fd->add_option("--density-col", da->x, "density column (_g_cm3 or _kg_m3 suffix)")->default_val("density_g_cm3");
  fd->add_option("--G-col", da->y, "shear modulus column (unit suffix)")->default_val("G_GPa");
  fd->add_option("--K-col", da->y2, "bulk modulus column (unit suffix)")->default_val("K_GPa");
  fd->add_option("--rho0", da->rho0, "theoretical maximum density")->default_val("1942 kg/m3");
  fd->add_option("--GU", da->GU, "upper-bound shear modulus G^U")->default_val("10.84 GPa");
  fd->add_option("--KU", da->KU, "upper-bound bulk modulus K^U")->default_val("10.52 GPa");
  fd->add_option("--confidence", da->confidence, "confidence level of the intervals")->default_val(0.95);
  fd->add_option("--out", da->out, "write the fits as JSON");
  fd->callback([da, write_out] {
    check_confidence(da->confidence);
    const CsvTable t = CsvTable::read(da->csv);
    const auto rho = scaled_column(t, da->x, dim::density, "--density-col");
    const double rho0 = quantity_option(da->rho0, dim::density, "--rho0");
    const double GU = quantity_option(da->GU, dim::pressure, "--GU"),
                 KU = quantity_option(da->KU, dim::pressure, "--KU");
    Json j = Json::object();
    if (t.has(da->y)) {
      const FitResult g =
          fit_density_law(rho, scaled_column(t, da->y, dim::pressure, "--G-col"), rho0, GU, da->confidence);
      fmt::print("G: ");
      print_fit(g);
      j["G"] = g.to_json();
    }
    if (t.has(da->y2)) {
      const FitResult k =
          fit_density_law(rho, scaled_column(t, da->y2, dim::pressure, "--K-col"), rho0, KU, da->confidence);
      fmt::print("K: ");
      print_fit(k);
      j["K"] = k.to_json();
    }
    if (!t.has(da->y) && !t.has(da->y2)) {
      throw InputError(fmt::format("{}: neither --G-col '{}' nor --K-col '{}' is a column", da->csv, da->y, da->y2));
    }
    write_out(da->out, j);
  });

  auto oa = std::make_shared<FitArgs>();
  auto sa = std::make_shared<AnalyzeArgs>();
  auto* fs = fit->add_subcommand("study", "analyse every run of a study and fit it (writes fits.json)");
  fs->add_option("STUDY_DIR", sa->dir, "study directory (study.json, runs/)")->required();
  fs->add_option("--out", oa->out, "output file (default STUDY_DIR/fits.json)");
  add_analysis_flags(fs, *sa);
  auto fsa = std::make_shared<StudyArgs>();
  add_study_flags(fs, *fsa);
  fs->callback([sa, oa, fsa] {
    StudyFitOptions o;
    apply_study_flags(*fsa, o);
    o.analysis = analysis_options(with_study_options(*sa));
    std::vector<MissingRun> missing;
    Json j = fit_study(load_study(sa->dir, o, &missing), o);
    if (!missing.empty()) j["missing_runs"] = missing_runs_json(missing);
    const std::string out = oa->out.empty() ? sa->dir + "/fits.json" : oa->out;
    json_write_file(out, j);
    fmt::print("wrote {}\n", out);
  });

  // ---- report ----
  auto ra = std::make_shared<AnalyzeArgs>();
  auto ro = std::make_shared<ReportOptions>();
  auto* rep = app.add_subcommand("report", "build STUDY_DIR/report/: figures, tables beside the paper, model card");
  rep->add_option("STUDY_DIR", ra->dir, "finished study directory (study.json, runs/<id>/)")->required();
  rep->add_option("--out", ro->out_dir, "report directory (default STUDY_DIR/report)");
  rep->add_flag("--reuse-analysis", ro->fits.reuse_analysis, "use the runs' existing analysis.json files");
  rep->add_option("--python", ro->python, "Python interpreter with numpy and matplotlib")
      ->default_val("/usr/bin/python3");
  add_analysis_flags(rep, *ra);
  auto rsa = std::make_shared<StudyArgs>();
  add_study_flags(rep, *rsa);
  rep->callback([ra, ro, rsa] {
    apply_study_flags(*rsa, ro->fits);
    if (ro->fits.reuse_analysis) {
      // the runs' analysis.json files are used as they are: analysis flags would be ignored
      const AnalyzeArgs& a = *ra;
      for (const auto& [flag, given] : {std::pair<const char*, bool>{"--window", !a.window.empty()},
                                        {"--plateau", !a.plateau.empty()},
                                        {"--strength-strain", !a.strength_strain.empty()},
                                        {"--window-signal", !a.window_signal.empty()},
                                        {"--window-tolerance", !a.tolerance.empty()},
                                        {"--ke-ie-limit", !a.ke_ie.empty()},
                                        {"--options", !a.options_file.empty()},
                                        {"--allow-unfinished", a.allow_unfinished}})
        if (given)
          throw InputError(
              fmt::format("report: {} changes the analysis, but --reuse-analysis uses the runs' "
                          "analysis.json as they are; drop one of the two",
                          flag));
      ro->fits.analysis = analysis_options(with_study_options(*ra, true));
    } else {
      ro->fits.analysis = analysis_options(with_study_options(*ra));
    }
    const std::string out = build_report(ra->dir, *ro);
    fmt::print("report written to {}/report.html (and report.md)\n", out);
  });
}

}  // namespace pbx::app
