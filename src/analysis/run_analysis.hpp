#pragma once
// `pbxmpm analyze RUN_DIR`: the whole analysis of one run directory (history.csv + run.json) into
// RUN_DIR/analysis.json. See docs/theory/analysis.md for every definition.
#include <optional>
#include <string>

#include "io/json.hpp"

namespace pbx {

class DeckTable;

struct AnalysisOptions {
  std::optional<double> window_lo, window_hi;  // linear window by hand (strain)
  // Curve on which the automatic window is found: "volume_average" (-<syy>, smooth because it
  // averages over all particles) or "punch" (rings with stress waves in explicit runs).
  std::string window_signal = "volume_average";
  double window_tolerance = 0.10;
  int window_min_points = 8;
  double window_min_span = 0;  // strain: the automatic window spans at least this much (0: points only)
  double window_max_strain = 0.02;
  double strength_max_strain = 0.03;
  double strength_plateau_from = 0.005;  // the strength is the mean stress from here to strength_max_strain
  std::optional<double> plateau_lo, plateau_hi;
  double ke_ie_limit = 0.05;
  // Largest share of the punch's compaction (box area lost) that may be taken up by overlapping
  // particle domains of different fields before the run is flagged (history column
  // field_overlap_m2_per_m; docs/theory/analysis.md).
  double overlap_limit = 0.25;
  // Largest accepted spread of K, G or E over the linear window's sub-windows (its first and its
  // last three quarters), half the range over the window's value: beyond it the moduli follow
  // single rows of a ringing curve and the run is warned about (docs/theory/analysis.md §3).
  double window_spread_limit = 0.10;
  // Largest accepted (KE + stress work)/punch work - 1 from the linear window's start: a run can
  // only lose energy (friction, contact, damping), so a gain beyond this is a numerical energy source.
  double energy_gain_limit = 0.05;
  bool allow_unfinished = false;
  int curve_points = 400;  // the curve stored in analysis.json is thinned to about this many points

  // Reads the [analysis] keys of docs/deck/analysis.md from a deck table (all optional).
  static AnalysisOptions from_deck(const DeckTable& t);
  void validate() const;  // throws InputError naming the offending option
  Json to_json() const;
};

// Analyses RUN_DIR; throws InputError naming a missing file, key or column.
Json analyze_run(const std::string& run_dir, const AnalysisOptions& opt);

// analyze_run + write RUN_DIR/analysis.json; returns the document.
Json analyze_run_to_file(const std::string& run_dir, const AnalysisOptions& opt);

}  // namespace pbx
