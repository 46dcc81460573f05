#pragma once
// Study-level results: every run of STUDY/study.json analysed, ensemble statistics per condition
// (mean +- std over seeds), and the paper's constitutive fits (Eq. 13-15, 19-22) with confidence
// intervals, plus Hashin-Shtrikman bounds. Written to fits.json for the report.
#include <optional>
#include <string>
#include <vector>

#include "analysis/hashin_shtrikman.hpp"
#include "analysis/json.hpp"
#include "analysis/run_analysis.hpp"

namespace pbx {

struct StudyFitOptions {
  double T0_K = 293.0;
  double GU = 10.84e9, KU = 10.52e9;  // paper's upper bounds (its ref. [41]), Pa
  std::optional<double> rho0;          // default: the runs' tmd_kg_m3, else 1942 kg/m3
  double eq14_lo_percent = 0.5, eq14_hi_percent = 3.0;  // Eq. 14 fitting window (plateau), % strain
  double confidence = 0.95;
  std::string paper_values;  // TOML with the paper's Table 3 (default: tools/report/paper_values.toml)
  AnalysisOptions analysis;
  bool reuse_analysis = false;  // use existing analysis.json files instead of re-analysing
};

struct StudyRun {
  std::string id;
  std::string dir;  // absolute
  Json entry;       // the run's entry in study.json
  Json analysis;    // its analysis.json
};

// Reads study.json and checks every run directory; throws one InputError listing everything that
// is missing or unfinished. Then analyses each run (writing RUN/analysis.json).
std::vector<StudyRun> load_study(const std::string& study_dir, const StudyFitOptions& opt);

Json fit_study(const std::vector<StudyRun>& runs, const StudyFitOptions& opt);

// The phases of a run for the Hashin-Shtrikman bounds: run.json "phases" when present, else the
// paper's Table 1 phases (TATB K = rho0 c0^2, G = 11.5 GPa; F2314 K = 0.33, G = 0.07 GPa) at
// 95:5 mass ratio with the given porosity as a third phase.
std::vector<Phase> paper_phases(double porosity);

// The paper's Table 3 refit (Eq. 13 by both methods), from the paper-values TOML.
Json paper_table3_refit(const std::string& paper_values_path, double confidence);

std::string default_paper_values_path();

}  // namespace pbx
