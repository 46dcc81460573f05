#include "analysis/study_fits.hpp"

#include <algorithm>
#include <cmath>
#include <set>
#include <filesystem>
#include <map>

#include <fmt/format.h>
#include <toml++/toml.h>

#include "analysis/density_law.hpp"
#include "analysis/report_files.hpp"
#include "analysis/ensemble.hpp"
#include "analysis/normalized_curve_law.hpp"
#include "analysis/temperature_law.hpp"
#include "core/error.hpp"

namespace fs = std::filesystem;

namespace pbx {

namespace {

double num(const Json& j, std::initializer_list<const char*> path) {
  const Json* p = &j;
  for (const char* k : path) {
    p = json_find(*p, k);
    if (!p) return std::nan("");
  }
  return p->is_number() ? json_number(*p) : std::nan("");
}

std::string str(const Json& j, const char* key, const std::string& def = "") {
  const Json* p = json_find(j, key);
  return p && p->is_string() ? json_string(*p) : def;
}

// Run temperature: study entry, else analysis (run.json) value.
double temperature_of(const StudyRun& r) {
  double T = num(r.entry, {"temperature_K"});
  return std::isfinite(T) ? T : num(r.analysis, {"temperature_K"});
}
// Measured specimen density (kg/m3), else the nominal study density.
double density_of(const StudyRun& r) {
  double rho = num(r.analysis, {"density_kg_m3"});
  if (std::isfinite(rho)) return rho;
  const double g = num(r.entry, {"density_g_cm3"});
  return std::isfinite(g) ? g * 1e3 : std::nan("");
}
std::string group_of(const StudyRun& r) {
  std::string g = str(r.entry, "group");
  if (g.empty()) {
    if (const Json* s = json_find(r.analysis, "study")) g = str(*s, "group");
  }
  return g;
}
// The deck key a run's group varies, as study.json (or its run.json) records it; empty in a
// study.json written before 2026-12-06 or by hand.
std::string key_of(const StudyRun& r) {
  std::string key = str(r.entry, "key");
  if (key.empty()) {
    if (const Json* s = json_find(r.analysis, "study")) key = str(*s, "key");
  }
  return key;
}
// The paper's sweep a run belongs to, by what its group varies: "temperature" (run.temperature)
// or "density" (packing.porosity) when the study gives that key two or more values (a reference
// group that fixes the temperature at 293 K is no sweep), "none" for any other key, whatever the
// group is called. Without keys the group's name decides, and a run without a group counts for
// both sweeps ("both"). `values` holds the distinct values each key takes in the study.
std::string sweep_of(const StudyRun& r, const std::map<std::string, std::set<std::string>>& values) {
  const std::string key = key_of(r);
  if (!key.empty()) {
    const auto it = values.find(key);
    if (it == values.end() || it->second.size() < 2) return "none";
    return key == "run.temperature" ? "temperature" : key == "packing.porosity" ? "density" : "none";
  }
  const std::string g = group_of(r);
  return g == "temperature" || g == "density" ? g : g.empty() ? "both" : "none";
}

struct Quantity {
  const char* name;
  std::initializer_list<const char*> path;
};
const Quantity kQuantities[] = {
    {"K_Pa", {"moduli", "K_Pa"}},
    {"G_Pa", {"moduli", "G_Pa"}},
    {"E_Pa", {"moduli", "E_Pa"}},
    {"M_Pa", {"moduli", "M_Pa"}},
    {"lambda_Pa", {"moduli", "lambda_Pa"}},
    {"nu", {"moduli", "nu"}},
    {"K_isotropic_Pa", {"moduli", "K_isotropic_Pa"}},
    {"lateral_coefficient", {"moduli", "lateral_coefficient"}},
    {"K_volume_average_Pa", {"moduli_volume_average", "K_Pa"}},
    {"G_volume_average_Pa", {"moduli_volume_average", "G_Pa"}},
    {"E_volume_average_Pa", {"moduli_volume_average", "E_Pa"}},
    {"strength_Pa", {"strength", "strength_Pa"}},
    {"peak_strength_Pa", {"strength", "peak_strength_Pa"}},
    {"stress_at_99_tmd_Pa", {"stress_at_99_tmd", "punch_stress_Pa"}},
    {"yield_stress_Pa", {"strength", "yield_stress_Pa"}},
    {"yield_strain", {"strength", "yield_strain"}},
    {"density_kg_m3", {"density_kg_m3"}},
    {"porosity", {"porosity"}},
    {"ke_ie_max_after_ramp", {"quasi_static", "ke_ie_max_after_ramp"}},
    {"ke_ie_max_from_window_start", {"quasi_static", "ke_ie_max_from_window_start"}},
    {"punch_vs_volume_rms_relative", {"agreement", "punch_vs_minus_syy", "rms_relative"}},
    {"interpenetration_share", {"interpenetration", "share_of_compaction"}},
    {"interpenetration_share_at_window_end", {"interpenetration", "share_of_compaction_at_window_end"}},
    {"energy_ratio_max", {"energy_balance", "max_ratio"}},
};

Json hs_json(const HashinShtrikmanBounds& b) {
  Json j = Json::object();
  j["K_lower_Pa"] = b.K_lower;
  j["K_upper_Pa"] = b.K_upper;
  j["G_lower_Pa"] = b.G_lower;
  j["G_upper_Pa"] = b.G_upper;
  return j;
}

std::vector<Phase> phases_of(const StudyRun& r, const StudyFitOptions& opt, std::string& source) {
  std::string why = "no phase source given";
  if (opt.run_phases) {
    try {
      return opt.run_phases(r, source);
    } catch (const InputError& e) {
      why = e.what();
    }
  }
  double phi = num(r.analysis, {"porosity"});
  if (!std::isfinite(phi)) phi = 0;
  source = fmt::format("the paper's Table 1 phases at the run's porosity (the run's own: {})", why);
  return paper_phases(phi);
}

// Hashin-Shtrikman bounds of one run's phases, with and without its pores (the pore-free composite
// compares with the paper's G^U, K^U), the phases themselves and where they come from.
Json bounds_json(const StudyRun& r, const StudyFitOptions& opt) {
  std::string source;
  const std::vector<Phase> ph = phases_of(r, opt, source);
  Json b = Json::object();
  b["run"] = r.id;
  b["phases_source"] = source;
  Json phases = Json::array();
  for (const auto& p : ph) {
    Json e = Json::object();
    e["name"] = p.name;
    e["K_Pa"] = p.bulk_modulus;
    e["G_Pa"] = p.shear_modulus;
    e["volume_fraction"] = p.volume_fraction;
    phases.push_back(std::move(e));
  }
  b["phases"] = phases;
  b["with_pores"] = hs_json(hashin_shtrikman_bounds(ph));
  std::vector<Phase> solid;
  double fs_sum = 0;
  for (const auto& p : ph) {
    if (p.bulk_modulus > 0 || p.shear_modulus > 0) {
      solid.push_back(p);
      fs_sum += p.volume_fraction;
    }
  }
  for (auto& p : solid) p.volume_fraction /= fs_sum;
  b["pore_free"] = hs_json(hashin_shtrikman_bounds(solid));
  return b;
}

}  // namespace

std::string default_paper_values_path() { return report_file("paper_values.toml"); }

std::vector<Phase> paper_phases(double porosity) {
  const double rho_t = 1934, rho_b = 2020, c0 = 2340;
  const double vt = 0.95 / rho_t, vb = 0.05 / rho_b;
  const double solid = 1.0 - porosity;
  std::vector<Phase> ph{{rho_t * c0 * c0, 11.5e9, solid * vt / (vt + vb), "TATB"},
                        {0.33e9, 0.07e9, solid * vb / (vt + vb), "F2314"}};
  if (porosity > 0) ph.push_back({0, 0, porosity, "pores"});
  return ph;
}

std::vector<StudyRun> load_study(const std::string& study_dir, const StudyFitOptions& opt,
                                 std::vector<MissingRun>* missing_runs) {
  const fs::path dir(study_dir);
  const fs::path sj = dir / "study.json";
  if (!fs::is_directory(dir)) throw InputError(fmt::format("study directory '{}' does not exist", study_dir));
  if (!fs::exists(sj)) {
    throw InputError(fmt::format(
        "{}: missing; a study directory holds study.json and runs/<id>/ (made by 'pbxmpm study')", sj.string()));
  }
  const Json study = json_read_file(sj.string());
  const Json* runs = json_find(study, "runs");
  if (!runs || !runs->is_array() || json_array(*runs).empty()) {
    throw InputError(fmt::format("{}: no \"runs\" array (or it is empty)", sj.string()));
  }
  std::vector<std::string> missing;
  std::vector<MissingRun> left_out;
  std::vector<StudyRun> out;
  for (const auto& e : json_array(*runs)) {
    StudyRun r;
    r.entry = e;
    r.id = str(e, "id");
    std::string rel = str(e, "dir", r.id.empty() ? "" : "runs/" + r.id);
    if (rel.empty()) throw InputError(fmt::format("{}: a run entry without \"id\" or \"dir\"", sj.string()));
    if (r.id.empty()) r.id = fs::path(rel).filename().string();
    const fs::path rd = dir / rel;
    r.dir = fs::absolute(rd).lexically_normal().string();
    if (!fs::is_directory(rd)) {
      missing.push_back(fmt::format("{}/ (run '{}' was not run)", rel, r.id));
      left_out.push_back({r.id, missing.back()});
      continue;
    }
    bool ok = true;
    for (const char* f : {"run.json", "history.csv"}) {
      if (!fs::exists(rd / f)) {
        missing.push_back(fmt::format("{}/{}", rel, f));
        ok = false;
      }
    }
    if (ok) {
      const Json rj = json_read_file((rd / "run.json").string());
      const std::string st = str(rj, "status", "unknown");
      if (st != "finished" && !opt.analysis.allow_unfinished) {
        missing.push_back(fmt::format("{}/run.json: status '{}', not 'finished'", rel, st));
        ok = false;
      }
    }
    if (ok && opt.reuse_analysis && !fs::exists(rd / "analysis.json")) {
      missing.push_back(fmt::format("{}/analysis.json", rel));
      ok = false;
    }
    if (ok)
      out.push_back(std::move(r));
    else
      left_out.push_back({r.id, missing.back()});
  }
  if (!missing.empty() && opt.partial && !out.empty()) {
    if (missing_runs) *missing_runs = left_out;
  } else if (!missing.empty()) {
    throw InputError(fmt::format("study '{}' is incomplete; missing or unfinished:\n  {}{}", study_dir,
                                 fmt::join(missing, "\n  "),
                                 opt.partial ? "\n(no run is finished, so not even a partial report can be made)"
                                             : "\n(--partial reports the finished runs alone)"));
  }
  for (auto& r : out) {
    r.analysis = opt.reuse_analysis ? json_read_file((fs::path(r.dir) / "analysis.json").string())
                                    : analyze_run_to_file(r.dir, opt.analysis);
  }
  return out;
}

Json missing_runs_json(const std::vector<MissingRun>& missing) {
  Json a = Json::array();
  for (const auto& m : missing) {
    Json e = Json::object();
    e["id"] = m.id;
    e["why"] = m.why;
    a.push_back(std::move(e));
  }
  return a;
}

Json paper_table3_refit(const std::string& path, double confidence) {
  Json j = Json::object();
  if (!fs::exists(path)) {
    j["note"] = fmt::format("paper values file '{}' not found; refit skipped", path);
    return j;
  }
  toml::table t;
  try {
    t = toml::parse_file(path);
  } catch (const toml::parse_error& e) {
    throw InputError(fmt::format("{}: {}", path, e.description()));
  }
  std::vector<double> T, s;
  if (auto* a = t["table3"]["T_K"].as_array()) {
    for (auto& v : *a) T.push_back(v.value<double>().value_or(std::nan("")));
  }
  if (auto* a = t["table3"]["strength_MPa"].as_array()) {
    for (auto& v : *a) s.push_back(v.value<double>().value_or(std::nan("")) * 1e6);
  }
  const double T0 = t["fits"]["temperature"]["T0_K"].value<double>().value_or(293.0);
  if (T.size() < 2 || T.size() != s.size()) {
    j["note"] = fmt::format("{}: [table3] T_K / strength_MPa missing or of different lengths", path);
    return j;
  }
  j["source"] = "paper Table 3 (compression strength vs temperature)";
  j["T_K"] = json_numbers(T);
  j["strength_Pa"] = json_numbers(s);
  j["T0_K"] = T0;
  j["nonlinear"] = fit_temperature_law_nonlinear(T, s, T0, confidence).to_json();
  j["loglinear"] = fit_temperature_law_loglinear(T, s, T0, confidence).to_json();
  if (auto a = t["fits"]["temperature"]["alpha"].value<double>()) j["paper_alpha"] = *a;
  if (auto s0 = t["fits"]["temperature"]["sigma0_MPa"].value<double>()) j["paper_sigma0_Pa"] = *s0 * 1e6;
  return j;
}

Json fit_study(const std::vector<StudyRun>& runs, const StudyFitOptions& opt) {
  Json out = Json::object();
  out["format"] = "pbxmpm-fits-1";
  out["confidence"] = opt.confidence;

  // Conditions: the seeds of one study value (study.json "group" and "value", as `pbxmpm study`
  // writes them) form one condition. Entries without a value (hand-made study.json files) group by
  // temperature and nominal density instead. The measured density cannot be the key: each seed's
  // packing lands on its own density within the porosity tolerance.
  struct Cond {
    std::string group, value;
    double T = 0, rho_nominal = 0;
    std::vector<const StudyRun*> runs;
  };
  std::map<std::string, std::set<std::string>> key_values;  // distinct study values per varied key
  for (const auto& r : runs)
    if (const std::string key = key_of(r); !key.empty()) key_values[key].insert(str(r.entry, "value"));
  std::map<std::string, std::string> sweep;  // per run id
  for (const auto& r : runs) sweep[r.id] = sweep_of(r, key_values);
  std::vector<Cond> conds;
  for (const auto& r : runs) {
    const std::string g = group_of(r);
    const std::string value = str(r.entry, "value");
    const double T = temperature_of(r);
    double rn = num(r.entry, {"density_g_cm3"});
    rn = std::isfinite(rn) ? rn * 1e3 : density_of(r);
    auto same = [&](const Cond& c) {
      if (c.group != g || c.value != value) return false;
      if (!value.empty()) return true;
      return std::fabs(c.T - T) < 0.5 &&
             (std::fabs(c.rho_nominal - rn) < 0.5 || (std::isnan(rn) && std::isnan(c.rho_nominal)));
    };
    auto it = std::find_if(conds.begin(), conds.end(), same);
    if (it == conds.end()) {
      conds.push_back({g, value, T, rn, {}});
      it = conds.end() - 1;
    }
    it->runs.push_back(&r);
  }
  Json cj = Json::array();
  for (const auto& c : conds) {
    Json e = Json::object();
    e["group"] = c.group;
    e["value"] = c.value;
    e["temperature_K"] = c.T;
    // the grouping key of conditions without a study value; with one, the seeds' densities differ
    // and their mean +- sd is stats.density_kg_m3
    if (c.value.empty()) e["density_nominal_kg_m3"] = c.rho_nominal;
    Json ids = Json::array();
    for (auto* r : c.runs) ids.push_back(r->id);
    e["runs"] = ids;
    Json stats = Json::object();
    for (const auto& q : kQuantities) {
      std::vector<double> v;
      for (auto* r : c.runs) v.push_back(num(r->analysis, q.path));
      stats[q.name] = ensemble_stat(v).to_json();
    }
    e["stats"] = stats;
    // the bounds of the condition's own materials (its first run): conditions may differ in
    // material (a stiffer binder), temperature and porosity
    e["hashin_shtrikman"] = bounds_json(*c.runs.front(), opt);
    e["sweep"] = sweep.at(c.runs.front()->id);
    cj.push_back(e);
  }
  out["conditions"] = cj;

  // The paper's fits need its sweeps: study groups that vary run.temperature and packing.porosity
  // (sweep_of; as examples/paper/*.toml). A study without them (its own question: groups
  // "reference" and "binder_x2" varying the binder) gets none of the paper's fits, and each note
  // says so instead of "0 points".
  auto in_group = [&](const StudyRun& r, const char* g) {
    const std::string& sw = sweep.at(r.id);
    return sw == g || sw == "both";
  };
  Json sweeps = Json::object();
  for (const char* g : {"temperature", "density"}) {
    sweeps[g] = int(std::count_if(runs.begin(), runs.end(), [&](const StudyRun& r) { return in_group(r, g); }));
  }
  out["paper_sweeps"] = sweeps;
  Json run_sweeps = Json::object();
  for (const auto& [id, sw] : sweep) run_sweeps[id] = sw;
  out["run_sweeps"] = run_sweeps;
  const bool has_T = json_number(*json_find(sweeps, "temperature")) > 0;
  const bool has_rho = json_number(*json_find(sweeps, "density")) > 0;
  const std::string no_T = "the study has no group varying run.temperature (the paper's sweep over temperature)";
  const std::string no_rho = "the study has no group varying packing.porosity (the paper's sweep over density)";

  // Eq. 13 on the temperature group (all seeds as individual points).
  std::vector<double> T, sc;
  for (const auto& r : runs) {
    if (!in_group(r, "temperature")) continue;
    const double t = temperature_of(r), s = num(r.analysis, {"strength", "strength_Pa"});
    if (std::isfinite(t) && std::isfinite(s)) {
      T.push_back(t);
      sc.push_back(s);
    }
  }
  Json eq13 = Json::object();
  eq13["T0_K"] = opt.T0_K;
  eq13["T_K"] = json_numbers(T);
  eq13["strength_Pa"] = json_numbers(sc);
  std::vector<double> distinct_T = T;
  std::sort(distinct_T.begin(), distinct_T.end());
  distinct_T.erase(
      std::unique(distinct_T.begin(), distinct_T.end(), [](double a, double b) { return std::fabs(a - b) < 0.5; }),
      distinct_T.end());
  if (distinct_T.size() >= 2) {
    eq13["nonlinear"] = fit_temperature_law_nonlinear(T, sc, opt.T0_K, opt.confidence).to_json();
    eq13["loglinear"] = fit_temperature_law_loglinear(T, sc, opt.T0_K, opt.confidence).to_json();
  } else {
    eq13["note"] = has_T ? "fewer than 2 temperatures: Eq. 13 not fitted" : no_T + ": Eq. 13 not fitted";
  }
  out["eq13"] = eq13;

  // Eq. 14 on the normalised curves at T0 (each run normalised by its own strength).
  std::vector<double> ep, sn;
  for (const auto& r : runs) {
    if (std::fabs(temperature_of(r) - opt.T0_K) > 0.5 || !in_group(r, "temperature")) continue;
    const double s = num(r.analysis, {"strength", "strength_Pa"});
    const Json* curve = json_find(r.analysis, "curve");
    if (!curve || !(s > 0)) continue;
    const auto& e = json_array(*json_find(*curve, "strain"));
    const auto& p = json_array(*json_find(*curve, "punch_stress_Pa"));
    for (std::size_t i = 0; i < e.size(); ++i) {
      if (!e[i].is_number() || !p[i].is_number()) continue;
      const double pct = 100.0 * json_number(e[i]);
      if (pct >= opt.eq14_lo_percent && pct <= opt.eq14_hi_percent) {
        ep.push_back(pct);
        sn.push_back(json_number(p[i]) / s);
      }
    }
  }
  Json eq14 = Json::object();
  eq14["T_K"] = opt.T0_K;
  eq14["window_percent"] = json_numbers({opt.eq14_lo_percent, opt.eq14_hi_percent});
  eq14["points"] = int(ep.size());
  if (ep.size() >= 4) {
    eq14["fit"] = fit_normalized_curve(ep, sn, opt.confidence).to_json();
  } else {
    eq14["note"] = has_T ? fmt::format("{} points at T0 = {} K in the Eq. 14 window: not fitted", ep.size(), opt.T0_K)
                         : no_T + ": Eq. 14 not fitted";
  }
  out["eq14"] = eq14;

  // Eq. 19-22 on the density group.
  std::vector<double> rho, Gs, Ks;
  std::set<std::string> conditions;  // study values: the seeds of one value differ a little in density
  double tmd = std::nan("");
  for (const auto& r : runs) {
    if (!std::isfinite(tmd)) tmd = num(r.analysis, {"specimen", "tmd_kg_m3"});
    if (!in_group(r, "density")) continue;
    const double d = density_of(r), G = num(r.analysis, {"moduli", "G_Pa"}), K = num(r.analysis, {"moduli", "K_Pa"});
    if (std::isfinite(d) && G > 0 && K > 0) {
      rho.push_back(d);
      Gs.push_back(G);
      Ks.push_back(K);
      // study.json of pbxmpm study names each run's value; a hand-written one (temperature_K,
      // density_g_cm3 only) is grouped by its density to 0.1 kg/m^3 instead of read as one condition
      const std::string value = str(r.entry, "value");
      conditions.insert(value.empty() ? fmt::format("rho {:.1f}", d) : value);
    }
  }
  const double rho0 = opt.rho0.value_or(std::isfinite(tmd) ? tmd : 1942.0);
  Json hsj = Json::object();
  hsj["rho0_kg_m3"] = rho0;
  hsj["GU_Pa"] = opt.GU;
  hsj["KU_Pa"] = opt.KU;
  hsj["density_kg_m3"] = json_numbers(rho);
  hsj["G_Pa"] = json_numbers(Gs);
  hsj["K_Pa"] = json_numbers(Ks);
  std::vector<double> distinct_rho = rho;
  std::sort(distinct_rho.begin(), distinct_rho.end());
  distinct_rho.erase(
      std::unique(distinct_rho.begin(), distinct_rho.end(), [](double a, double b) { return std::fabs(a - b) < 0.05; }),
      distinct_rho.end());
  // Two densities must be two study conditions: the seeds of one porosity scatter by a few kg/m^3
  // (the packer's porosity tolerance), and a power law through that scatter is noise (n = -14).
  if (distinct_rho.size() >= 2 && conditions.size() >= 2) {
    hsj["G"] = fit_density_law(rho, Gs, rho0, opt.GU, opt.confidence).to_json();
    hsj["K"] = fit_density_law(rho, Ks, rho0, opt.KU, opt.confidence).to_json();
  } else {
    hsj["note"] = has_rho ? "fewer than 2 density conditions: Eq. 19-22 not fitted" : no_rho + ": Eq. 19-22 not fitted";
  }
  out["density_law"] = hsj;
  if (has_T) {
    out["paper_table3_refit"] =
        paper_table3_refit(opt.paper_values.empty() ? default_paper_values_path() : opt.paper_values, opt.confidence);
  } else {
    Json refit = Json::object();
    refit["note"] = no_T + ": the paper's Table 3 is not refitted";
    out["paper_table3_refit"] = refit;
  }
  return out;
}

}  // namespace pbx
