#pragma once
// A study: one base deck and a list of runs (groups of values of one deck key, times seeds),
// each run a whole die-compression simulation followed by its analysis. The runs still to do are
// spread over MPI ranks (rank r takes the pending runs r, r + n, ...; OpenMP inside each run), so a
// resumed study keeps every rank busy; without MPI they run in turn.
// A study that stops can be started again: finished runs (run.json "finished" and analysis.json
// present) are skipped, an interrupted run continues from its last checkpoint. Layout: STUDY/study.json,
// STUDY/runs/<id>/{deck.toml, history.csv, run.json, analysis.json, snapshots/}, STUDY/analysis.toml (the study deck's
// [analysis] table, read by `pbxmpm report` and `fit study` when no analysis options are given), STUDY/report/.
#include <string>
#include <vector>

#include "analysis/run_analysis.hpp"

namespace pbx {

struct StudyRunSpec {
  std::string id;
  std::string group;
  std::string key;          // the deck key the group varies (the paper's sweeps: run.temperature, packing.porosity)
  std::string value_label;  // as written in the study deck
  long seed = 1;
  std::vector<std::pair<std::string, std::string>> set;  // dotted key -> TOML value text
};

struct StudySpec {
  std::string name;
  std::string deck;       // the study deck itself, absolute path (study.json: what `status` suggests rerunning)
  std::string base_deck;  // absolute path
  std::string base_text;
  std::vector<StudyRunSpec> runs;
  // The study deck's optional [analysis] table, applied to every run, so all runs of a study are
  // analysed with one linear window (automatic windows can end at different strains per run).
  AnalysisOptions analysis;
  std::string analysis_text;  // that table as TOML ("" if none): written to STUDY/analysis.toml
};

// Reads and validates a study deck (unknown keys are errors naming the key).
StudySpec read_study(const std::string& file);

// `--set KEY=VALUE` options of `pbxmpm study` and `pbxmpm check`, applied to every run after the
// study's [study.set] and before each run's group key and seed: a key a group varies, and the
// seeds, are refused (InputError naming the option).
void apply_set_options(StudySpec& s, const std::vector<std::string>& set);

// Letters, digits, '_', '-', '.' and not starting with '.' or '-': safe as one folder name.
bool is_folder_name(const std::string& name);

// The base deck with the run's overrides applied, as TOML text.
std::string run_deck_text(const StudySpec& s, const StudyRunSpec& r);
// Builds every run's deck and scene (specimens packed) as the study would before its first run;
// throws InputError naming the run deck's key. Returns the number of runs.
int check_study(const StudySpec& s);

struct StudyOptions {
  std::string out_dir;
  int threads = 0;
  bool report = true;
  bool progress = true;
  // Run only these run ids (empty: all). Unselected unfinished runs are neither checked nor run;
  // finished runs are always deck-checked and re-analysed; the report is built only when every
  // run of the study has finished. For studies too long for one sitting.
  std::vector<std::string> only;
  // Each run writes runs/<id>/checkpoint.h5 every this many history rows (0: never); a pending
  // run that has one (from the same deck) continues from it instead of starting over, and its
  // checkpoint is deleted when it finishes.
  int checkpoint_every = 10;
};

// Indices of the runs rank `rank` of `size` runs: the pending ones (pending[i] true), dealt round
// robin in study order.
std::vector<std::size_t> runs_of_rank(const std::vector<bool>& pending, int size, int rank);

// What run_study returns when it started no run (an invalid or changed deck, a folder another
// process writes, a study folder that cannot be written): the messages are on stderr.
inline constexpr int kStudyNotStarted = -1;
// run_study's result when a signal stopped it (the interrupted run saved a checkpoint).
inline constexpr int kStudyInterrupted = -2;

// Runs (or resumes) the study; returns the number of runs that failed, or kStudyNotStarted.
int run_study(const StudySpec& s, const StudyOptions& opt);

// The ranks an MPI launcher started this process among (Open MPI's mpirun, or a PMI launcher such
// as MPICH's or Slurm's `srun --mpi=pmi2`), read from the launcher's environment so that a plain
// run needs no MPI runtime; 0 when no launcher started it.
int launched_ranks();

}  // namespace pbx
