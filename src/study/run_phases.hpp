#pragma once
// The phases of a study run for the Hashin-Shtrikman bounds, from the run's own deck and particles:
// each material of RUN/deck.toml is built at the run temperature and probed as one material point
// (no grid): a volumetric strain step of 1e-6 gives K, a shear step of 1e-6 gives G, each read
// after a hold of the loading time t_load = (middle of the linear window) / (punch speed / die
// height), so a viscoelastic binder contributes its relaxation modulus G(t_load a_T) at the run
// temperature, the modulus the window's slope sees, not its glassy or rubbery limit. Volume
// fractions are the materials' particle counts (particles all start with one volume, h^2 in 2-D)
// scaled to the particles' share of the die, 1 - porosity (run.json); the pores are a third phase.
#include <string>
#include <vector>

#include "analysis/study_fits.hpp"

namespace pbx {

struct RunPhases {
  std::vector<Phase> phases;  // named by the deck's material names, and "pores"; fractions of the die's box
  double temperature_K = 0;
  double load_time_s = 0;  // t_load above
};

// Throws InputError naming the file and key when RUN/deck.toml, run.json or analysis.json lacks what
// is needed (a material with particles missing from the deck, no die, no linear window).
RunPhases run_phases(const StudyRun& run);

// Adapter for StudyFitOptions::run_phases.
std::vector<Phase> run_phases_for_bounds(const StudyRun& run, std::string& source);

}  // namespace pbx
