#pragma once
// Drives a Solver to the end of a run and writes what a user reads: history.csv (one row per
// reporting interval, forces averaged over it from the exact contact impulses), snapshots,
// run.json and a progress display. On an instability it stops, writes a last snapshot and marks
// run.json "failed" with the message, keeping every row written before.
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "contact/field_overlap.hpp"
#include "io/checkpoint.hpp"
#include "io/csv_writer.hpp"
#include "io/deck.hpp"
#include "io/json.hpp"
#include "io/output_lock.hpp"
#include "io/snapshot.hpp"
#include "solver/solver.hpp"
#include "run/thread_count.hpp"

namespace pbx {

// What one history row reports (die columns are zero when the run has no die).
struct Measurement {
  double t = 0, dt = 0, strain = 0, punch_velocity = 0;
  double punch_force = 0, punch_stress = 0;  // compression positive
  double wall_left = 0, wall_right = 0, wall_bottom = 0, wall_stress = 0;
  Sym3 mean_stress;  // box volume average, tension positive
  double kinetic = 0, internal = 0, dissipated = 0, punch_work = 0, ke_ie = 0;
  // the parts of `dissipated`: each material's plastic and viscous work (materials order), then the
  // contact's friction work
  std::vector<double> dissipated_parts;
  double max_speed = 0;  // the fastest deformable particle, m/s (a local instability shows here first)
  double mass = 0;
  std::vector<double> momentum, com_velocity;   // D components
  std::vector<std::vector<double>> body_force;  // per rigid body: force ON the specimen (D)
  // Per contact material pair (Runner::contact_pairs()): normal and shear force summed over the
  // interface nodes, then, when the materials differ, the net force on the first (D), N (per m).
  std::vector<std::vector<double>> pair_force;
  // Area where the particle domains of different fields overlap (contact/field_overlap.hpp),
  // m^2 per m; empty when not measured (3-D, or a single deformable field).
  std::vector<double> field_overlap;
  // Energy the binder-layer springs hold (part of internal; runs with binder_layer laws only), J/m.
  std::vector<double> layer_energy;
};

struct RunOptions {
  std::string out_dir;  // empty: write nothing (tests)
  int threads = 0;      // 0: chosen from the scene size (run/thread_count.hpp)
  bool progress = true;
  Json deck;                         // the validated deck (for run.json)
  Json study;                        // {"group": ..., ...} when the run belongs to a study; null otherwise
  std::string deck_text, deck_name;  // stored in checkpoints to rebuild the scene on restart
  int checkpoint_every = 0;          // write DIR/checkpoint.h5 every this many history rows (0 = never)
  // ... and at the first history row after this many wall seconds since the last one (0 = never):
  // a long run loses at most this much to a crash or a kill -9.
  double checkpoint_wall_s = 600;
  // SIGINT/SIGTERM finish the run up to its next history row, write a checkpoint and run.json
  // "interrupted", then throw Interrupted (a second signal stops at once).
  bool catch_signals = true;
  // In a study: the run's place ("run 2/4"), shown in the progress lines with the ETA of the
  // study (this run's ETA plus `runs_after` more runs as long as this one is taking).
  std::string progress_label;
  int runs_after = 0;
  // A run decomposed over MPI ranks (issue 28; docs/architecture.md, "One run over many ranks"):
  // this rank's exchange (null: one process) and the whole scene's mass threshold. Every rank takes
  // every collective step (sums, rows, snapshots); rank 0 alone writes files and shows progress.
  // Checkpoints are not written yet (a signal stops the run without one).
  ScatterExchange* exchange = nullptr;
  double mass_threshold = 0;
  int rank = 0, ranks = 1;
};

// The options a run takes from its deck: the validated deck as JSON (run.json), its text and name
// (checkpoints store them to rebuild the scene on restart), and the output folder. The caller adds
// threads, progress and checkpointing.
RunOptions run_options_for(const Deck& deck, const std::string& deck_name, const std::string& out_dir);

// Seconds until the study ends: the current run's remaining time plus `runs_after` runs of the
// length this one is projected to have, from `wall_s` spent since the fraction `frac_at_start`
// of the run (a restart) to `frac`; negative when not yet known.
double study_eta_s(double wall_s, double frac, double frac_at_start, int runs_after);

// This machine's name as run.json records it ("host"), with quotes and control characters replaced.
std::string host_name();

template <int D>
class Runner {
 public:
  // restart = true keeps an existing history.csv (resume() truncates it to the checkpoint's rows).
  Runner(Scene<D>& scene, RunOptions opt, bool restart = false);
  // Runs to the end; calls on_row after each history row (tests observe the run this way).
  void run(const std::function<void(const Measurement&)>& on_row = {});
  Solver<D>& solver() { return solver_; }
  const std::vector<std::string>& columns() const { return columns_; }
  const std::vector<MaterialPair>& contact_pairs() const { return contact_pairs_; }
  static std::vector<double> row_values(const Measurement& m, int nbodies);
  Measurement measure();
  void write_snapshot();
  void write_checkpoint(const std::string& file) const;
  // Restores the state saved in a checkpoint; run() then continues from it, appending to
  // history.csv (truncated to the rows the checkpoint had written).
  void resume(const CheckpointData& c);

 private:
  void write_run_json(const std::string& status, const std::string& message) const;
  void clear_previous_run() const;
  void stop_interrupted();
  std::string this_and_earlier_versions() const;  // code versions of all segments, "; "-separated
  void report_progress(const Measurement& m, bool final);
  std::string first_non_finite_particle() const;
  // The field overlap of the whole specimen (every rank's particles in a decomposed run).
  double field_overlap_area();
  // a per-particle array over every rank, in storage order (checkpoints), and the layout's fingerprint
  std::vector<double> whole_array(const std::vector<double>& mine) const;
  double whole_layout_fingerprint() const;
  Scene<D>& sc_;
  RunOptions opt_;
  Solver<D> solver_;
  // saves_: the run saves files (the same on every rank); writer_: this process writes them
  bool saves_ = false, writer_ = false;
  // The whole specimen's particles, their mass and initial volume (run.json), over every rank.
  struct Whole {
    std::size_t particles = 0;
    double mass = 0, volume0 = 0;
    std::vector<std::size_t> by_material;
  } whole_;
  OutputLock lock_;  // before the files it guards: released after they are closed
  CsvWriter history_;
  SnapshotWriter snapshots_;
  std::vector<std::string> columns_;
  std::vector<MaterialPair> contact_pairs_;  // material pairs with contact columns in history.csv
  std::optional<FieldOverlap> overlap_;      // 2-D with several deformable fields
  double t_last_row_ = 0, punch_work_ = 0, wall_start_ = 0, last_progress_ = -1, last_progress_wall_ = 0;
  // A restarted run: wall seconds of its earlier segments (run.json reports the whole run), and
  // the step and time fraction this segment started at (progress rates count this segment only).
  double wall_before_ = 0, frac_at_start_ = 0;
  long steps_at_start_ = 0;
  long steps_unclocked_ = 0;  // steps made before a checkpoint that did not record its wall time
  int restarts_ = 0;
  std::string code_versions_;  // of the earlier segments, then this one
  std::string run_id_;         // random at a fresh start, kept by restarts (run.json, checkpoint)
  double last_checkpoint_wall_ = 0;
  int next_row_ = 0, next_snapshot_ = 0, rows_written_ = 0;
  bool resumed_ = false;
  bool tty_ = false;
  ThreadChoice threads_;
};

// True once SIGINT or SIGTERM arrived during the last Runner::run, also when that run still reached
// its end (the signal came after its last checkpoint row): a study must then stop, not start the next run.
bool stop_signal_received();

}  // namespace pbx
