#pragma once
// Study-level results: every run of STUDY/study.json analysed, ensemble statistics per condition
// (mean +- std over seeds), and the paper's constitutive fits (Eq. 13-15, 19-22) with confidence
// intervals where the study has the paper's sweeps, plus Hashin-Shtrikman bounds per condition.
// Written to fits.json for the report.
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "analysis/hashin_shtrikman.hpp"
#include "io/json.hpp"
#include "analysis/run_analysis.hpp"

namespace pbx {

struct StudyRun;

struct StudyFitOptions {
  double T0_K = 293.0;
  double GU = 10.84e9, KU = 10.52e9;                    // paper's upper bounds (its ref. [41]), Pa
  std::optional<double> rho0;                           // default: the runs' tmd_kg_m3, else 1942 kg/m3
  double eq14_lo_percent = 0.5, eq14_hi_percent = 3.0;  // Eq. 14 fitting window (plateau), % strain
  double confidence = 0.95;
  std::string paper_values;  // TOML with the paper's Table 3 (default: tools/report/paper_values.toml)
  AnalysisOptions analysis;
  bool reuse_analysis = false;  // use existing analysis.json files instead of re-analysing
  // Use the finished runs of an incomplete study instead of refusing it; the runs left out are
  // returned by load_study and named in fits.json ("missing_runs") and at the top of the report.
  bool partial = false;
  // The phases of a run for the Hashin-Shtrikman bounds, with a sentence saying where they come
  // from (the study layer builds them from the run's own materials: study/run_phases.hpp). Unset,
  // or throwing InputError: the paper's Table 1 phases, and the source says why.
  std::function<std::vector<Phase>(const StudyRun&, std::string& source)> run_phases;
};

struct StudyRun {
  std::string id;
  std::string dir;  // absolute
  Json entry;       // the run's entry in study.json
  Json analysis;    // its analysis.json
};

// A run of study.json that load_study left out, and why.
struct MissingRun {
  std::string id, why;
};

// Reads study.json and checks every run directory; throws one InputError listing everything that
// is missing or unfinished (with opt.partial: lists it in `missing` instead, and throws only when
// no run is usable). Then analyses each run (writing RUN/analysis.json).
std::vector<StudyRun> load_study(const std::string& study_dir, const StudyFitOptions& opt,
                                 std::vector<MissingRun>* missing = nullptr);

Json fit_study(const std::vector<StudyRun>& runs, const StudyFitOptions& opt);

// [{"id": ..., "why": ...}, ...]: the runs a partial fit or report left out (fits.json "missing_runs").
Json missing_runs_json(const std::vector<MissingRun>& missing);

// The paper's Table 1 phases (TATB K = rho0 c0^2, G = 11.5 GPa; F2314 K = 0.33, G = 0.07 GPa) at 95:5
// mass ratio with the given porosity as a third phase: the bounds' fallback when
// StudyFitOptions::run_phases is unset or fails.
std::vector<Phase> paper_phases(double porosity);

// The paper's Table 3 refit (Eq. 13 by both methods), from the paper-values TOML.
Json paper_table3_refit(const std::string& paper_values_path, double confidence);

std::string default_paper_values_path();

}  // namespace pbx
