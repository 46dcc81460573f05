// `pbxmpm run DECK` and `pbxmpm check DECK`.
#include <chrono>
#include <cstdlib>
#include <cstdio>
#include <fstream>
#include <iterator>

#include <CLI/CLI.hpp>
#include <fmt/format.h>

#include "app/commands.hpp"
#include "setup/build_scene.hpp"
#include "core/error.hpp"
#include "io/deck.hpp"
#include "io/deck_override.hpp"
#include <filesystem>

#include "io/checkpoint.hpp"
#include "run/runner.hpp"
#include "study/study.hpp"

#ifdef PBXMPM_HAVE_MPI
#include <mpi.h>

#include "distributed/strip_exchange.hpp"
#include "distributed/strip_partition.hpp"
#endif

namespace pbx::app {

namespace {

struct RunArgs {
  std::string deck, out = "out/run", restart;
  std::vector<std::string> set;
  int threads = 0, checkpoint_every = 0;
  double checkpoint_minutes = 10;
  bool quiet = false;
};

// The deck file with --set overrides applied; relative paths in it still resolve beside the file.
Deck deck_from_file_with(const std::string& file, const std::vector<std::string>& set) {
  std::ifstream in(file);
  if (!in) throw InputError(fmt::format("cannot open deck '{}'", file));
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  std::vector<DeckOverride> ov;
  for (const auto& s : set) ov.push_back(parse_override_option(s));
  // messages give lines of the rewritten deck, so they name it as such
  return Deck::from_string(deck_with_overrides(text, file, ov), file + " (as rewritten by --set)",
                           std::filesystem::path(file).parent_path().string());
}

template <int D>
void check_deck(const std::string& file, Deck& deck) {
  Scene<D> scene = build_scene<D>(deck);
  deck.check_unused();
  auto count = [](std::size_t n, const char* one, const char* many) {
    return fmt::format("{} {}", n, n == 1 ? one : many);
  };
  std::string nodes = std::to_string(scene.grid.n[0]);
  for (int d = 1; d < D; ++d) nodes += " x " + std::to_string(scene.grid.n[d]);
  std::printf("%s: valid %d-D deck. %s in %s, %s, %s, grid %s nodes (h = %.4g m), end time %.4g s\n", file.c_str(), D,
              count(scene.particles.size(), "particle", "particles").c_str(),
              count(scene.materials.size(), "material", "materials").c_str(),
              count(static_cast<std::size_t>(scene.deformable_fields), "deformable field", "deformable fields").c_str(),
              count(scene.bodies.size(), "rigid body", "rigid bodies").c_str(), nodes.c_str(), scene.grid.h,
              scene.control.end_time);
}

template <int D>
void run_deck(Deck& deck, const RunArgs& args, const std::string& deck_name, const CheckpointData& ck) {
  Scene<D> scene = build_scene<D>(deck);
  deck.check_unused();
  RunOptions opt = run_options_for(deck, deck_name, args.out);
  opt.threads = args.threads;
  opt.progress = !args.quiet;
  opt.checkpoint_every = args.checkpoint_every;
  opt.checkpoint_wall_s = 60.0 * args.checkpoint_minutes;
  Runner<D> runner(scene, opt, !args.restart.empty());
  if (!args.restart.empty()) runner.resume(ck);
  // deformable velocity fields and rigid bodies told apart (the grid holds one field per body too)
  const int bodies = static_cast<int>(scene.bodies.size());
  fmt::print(stderr,
             "pbxmpm: {}{}: {} particles, {} x {}{} nodes ({}-D), {} deformable field{}{}, end time {:.4g} s -> {}\n",
             args.restart.empty() ? "" : "restart of ", deck_name, scene.particles.size(), scene.grid.n[0],
             scene.grid.n[1], D == 3 ? fmt::format(" x {}", scene.grid.n[D - 1]) : std::string(), D,
             scene.deformable_fields, scene.deformable_fields == 1 ? "" : "s",
             bodies == 0 ? std::string() : fmt::format(" and {} rigid bod{}", bodies, bodies == 1 ? "y" : "ies"),
             scene.control.end_time, args.out);
  const auto t0 = std::chrono::steady_clock::now();
  try {
    runner.run();
  } catch (const InstabilityError&) {
    // the closing line of a run that stopped: how far it got and where its rows are (main prints why)
    std::fprintf(stderr,
                 "pbxmpm: stopped after %ld steps in %.1f s; what it wrote is in %s (history.csv, run.json "
                 "with status 'failed' and the reason)\n",
                 runner.solver().step_count(),
                 std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(), args.out.c_str());
    throw;
  }
  // one closing line: what happened, how long, where the results are
  std::fprintf(stderr, "pbxmpm: finished: %ld steps in %.1f s; results in %s (history.csv, run.json%s)\n",
               runner.solver().step_count(),
               std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(), args.out.c_str(),
               scene.control.snapshots > 0 ? ", snapshots/snapshots.xmf" : "");
}

#ifdef PBXMPM_HAVE_MPI
// One run over the ranks mpirun started (issue 28; docs/architecture.md, "One run over many ranks"):
// every rank builds the whole scene (the same deck, the same seed), the strips are shared out by
// particle count, each rank keeps its strips' particles and steps them with the parity exchange;
// rank 0 writes the files and the checkpoints (the one-process file, gathered), and a restart on any
// number of ranks reads it. The history is the one-process run's to the bit.
template <int D>
void run_deck_over_ranks(Deck& deck, const RunArgs& args, const std::string& deck_name, const CheckpointData& ck) {
  int init = 0;
  MPI_Initialized(&init);
  // Funneled: with --threads N OpenMP threads live beside MPI, and only the master thread calls it
  // (the exchange runs between the parallel regions). Open MPI gives at least this level.
  int provided = 0;
  if (!init) MPI_Init_thread(nullptr, nullptr, MPI_THREAD_FUNNELED, &provided);
  int rank = 0, size = 1;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  MPI_Comm_size(MPI_COMM_WORLD, &size);
  int code = 0;
  try {
    // every rank builds the same scene; rank 0 says what it noticed
    Scene<D> scene = build_scene<D>(deck, rank == 0 ? SceneNotes::print : SceneNotes::quiet);
    deck.check_unused();
    // USF and MUSL's passes have no exchange yet (docs/architecture.md, "One run over many ranks")
    if (scene.settings.integrator != Integrator::usl)
      throw InputError(
          "solver.integrator: a run over several MPI ranks steps with \"usl\" only (USF and MUSL are not "
          "split over ranks yet); set it to \"usl\" or run on one process");
    // the whole scene's strips and mass threshold, before each rank keeps its part
    std::vector<long> begin;
    long width = 0, strips = 0;
    double mass_threshold = 0;
    {
      const Solver<D> whole(scene);
      begin = whole.strips().begin;
      width = whole.strips().width;
      strips = whole.strips().strips;
      mass_threshold = whole.mass_threshold();
    }
    // a rank between two others keeps its two stray zones (2 x width + 4 node lines each) apart
    const long min_strips = size <= 2 ? 1 : (3 * width + 3) / width;
    if (strips < size * min_strips) {
      const long most = std::max(strips >= 2 ? 2L : 1L, strips / ((3 * width + 3) / width));
      throw InputError(
          fmt::format("pbxmpm run: the grid has {} strips of {} cells along x, too few for {} MPI ranks "
                      "(a rank takes whole strips, {} or more when it has a neighbour on each side): "
                      "use at most {} ranks",
                      strips, width, size, min_strips, most));
    }
    const StripPartition part = partition_strips(begin, size, min_strips);
    const long first = part.first[static_cast<std::size_t>(rank)], end = part.first[static_cast<std::size_t>(rank) + 1];
    const std::size_t total = scene.particles.size();
    keep_particle_range(scene, static_cast<std::size_t>(begin[static_cast<std::size_t>(first)]),
                        static_cast<std::size_t>(begin[static_cast<std::size_t>(end)]));
    StripExchange<D> exchange(MPI_COMM_WORLD, scene.grid, &scene.layer_data.sums, width, strips, first, end,
                              scene.settings.kernel != Kernel::linear);
    RunOptions opt = run_options_for(deck, deck_name, args.out);
    opt.threads = args.threads;
    opt.progress = !args.quiet && rank == 0;
    opt.checkpoint_every = args.checkpoint_every;
    opt.checkpoint_wall_s = 60.0 * args.checkpoint_minutes;
    opt.exchange = &exchange;
    opt.mass_threshold = mass_threshold;
    opt.rank = rank;
    opt.ranks = size;
    // a restart: every rank reads the checkpoint (the one-process file) and keeps its strips' part
    Runner<D> runner(scene, opt, !args.restart.empty());
    if (!args.restart.empty()) runner.resume(ck);
    if (rank == 0)
      fmt::print(stderr, "pbxmpm: {}: {} particles over {} MPI ranks ({} strips), {} deformable fields -> {}\n",
                 deck_name, total, size, strips, scene.deformable_fields, args.out);
    const auto t0 = std::chrono::steady_clock::now();
    runner.run();
    if (rank == 0)
      std::fprintf(
          stderr, "pbxmpm: finished: %ld steps in %.1f s over %d ranks; results in %s (history.csv, run.json%s)\n",
          runner.solver().step_count(), std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(),
          size, args.out.c_str(), scene.control.snapshots > 0 ? ", snapshots/snapshots.xmf" : "");
  } catch (const InstabilityError& e) {
    // every rank stops in the same step (the solver's verdicts are collective); the culprit's rank
    // says why, rank 0 through main
    if (rank != 0 && std::string(e.what()).find("another rank") == std::string::npos)
      std::fprintf(stderr, "pbxmpm: rank %d: run stopped, unstable: %s\n", rank, e.what());
    if (rank == 0) {
      MPI_Finalize();
      throw;
    }
    code = 3;
  } catch (const Interrupted& e) {
    if (rank == 0) {
      MPI_Finalize();
      throw;
    }
    code = 130;
  } catch (const std::exception& e) {
    // an error of one rank (bad input is found by all, an output file only by rank 0): the others
    // may wait in a collective step, so the whole run is stopped
    const bool input = dynamic_cast<const InputError*>(&e) != nullptr;
    const bool output = dynamic_cast<const OutputError*>(&e) != nullptr;
    std::fprintf(stderr, "pbxmpm: rank %d: %s: %s\n", rank,
                 input    ? "input error"
                 : output ? "output error"
                          : "error",
                 e.what());
    std::fflush(stderr);
    MPI_Abort(MPI_COMM_WORLD, input ? 2 : output ? 4 : 1);
  }
  MPI_Finalize();
  if (code != 0) std::exit(code);
}
#endif

}  // namespace

void register_run(CLI::App& app) {
  auto args = std::make_shared<RunArgs>();
  auto* run = app.add_subcommand("run", "Run the simulation a deck describes");
  run->add_option("deck", args->deck, "TOML deck (not needed with --restart)")->check(CLI::ExistingFile);
  run->add_option("--out,-o", args->out, "output directory (history.csv, run.json, snapshots/)");
  run->add_option("--checkpoint-every", args->checkpoint_every,
                  "write OUT/checkpoint.h5 every N history rows (it is overwritten each time; 0: by the minutes only)")
      ->check(CLI::Range(0, 1000000));
  run->add_option("--checkpoint-minutes", args->checkpoint_minutes,
                  "also write OUT/checkpoint.h5 at the first history row after this many minutes since the last one "
                  "(0: never)")
      ->check(CLI::Range(0.0, 1e6))
      ->capture_default_str();
  run->add_option("--restart", args->restart,
                  "continue the run saved in this checkpoint, in the checkpoint's folder (its deck, its history.csv)")
      ->check(CLI::ExistingFile);
  run->add_option("--threads,-t", args->threads,
                  "OpenMP threads (default: OMP_NUM_THREADS, else one per 50,000 particles up to the cores)")
      ->check(CLI::Range(1, 1024))
      ->default_str("auto");
  run->add_option("--set", args->set,
                  "override a deck key before the run, KEY=VALUE in TOML (e.g. --set 'grid.cell_size=\"10 um\"'); "
                  "repeatable; checked like the deck, and saved in run.json and the checkpoint");
  run->add_flag("--quiet,-q", args->quiet, "no progress display");
  run->callback([args, run] {
    // Every rank would run the whole deck into the same folder (the second finds it locked and
    // mpirun then stops the first mid-run): one run is one process until a domain decomposition
    // exists (docs/architecture.md, "Parallelism").
    const int ranks = launched_ranks();
#ifndef PBXMPM_HAVE_MPI
    if (ranks > 1)
      throw InputError(fmt::format(
          "pbxmpm run: started as {} MPI ranks, but this pbxmpm was built without MPI: one run is one process. "
          "Use its OpenMP threads (pbxmpm run --threads N, or OMP_NUM_THREADS)",
          ranks));
#endif
    if (args->out.empty())
      throw InputError("--out: an empty folder name (an unset shell variable?); give the output folder");
    Deck deck = Deck::from_string("", "");
    CheckpointData ck;
    std::string deck_name = args->deck;
    if (!args->restart.empty()) {
      // the checkpoint carries its deck: a deck given beside it would be ignored, and an edited one
      // taken for the one in effect
      if (!args->set.empty())
        throw InputError("pbxmpm run: --set with --restart: the run continues with the deck saved in its checkpoint");
      if (!args->deck.empty())
        throw InputError(
            fmt::format("pbxmpm run: give a deck or --restart CHECKPOINT, not both (the run continues "
                        "with the deck saved in '{}')",
                        args->restart));
      ck = read_checkpoint(args->restart);
      // relative paths in the deck (specimen.packing_dir) resolve against the original deck's folder
      deck = Deck::from_string(ck.deck_text, ck.deck_name, std::filesystem::path(ck.deck_name).parent_path().string());
      deck_name = ck.deck_name;
      // A run continues in its own folder: its history.csv holds the rows the checkpoint counts, and
      // another folder's history (another run) would be cut and appended to.
      const auto parent = std::filesystem::path(args->restart).parent_path();
      const std::string folder = parent.empty() ? "." : parent.string();
      if (run->count("--out") > 0) {
        std::error_code e1, e2;
        if (!std::filesystem::equivalent(folder, args->out, e1) || e1 || e2)
          throw InputError(
              fmt::format("pbxmpm run: --restart continues the run in the checkpoint's own folder '{}'; "
                          "--out '{}' is another folder (copy the whole run folder to continue it "
                          "elsewhere)",
                          folder, args->out));
      }
      args->out = folder;
    } else if (args->deck.empty()) {
      throw InputError("pbxmpm run: give a deck, or --restart CHECKPOINT");
    } else if (args->set.empty()) {
      deck = Deck::from_file(args->deck);
    } else {
      deck = deck_from_file_with(args->deck, args->set);
    }
#ifdef PBXMPM_HAVE_MPI
    if (ranks > 1) {
      if (deck_dimension(deck) == 3)
        run_deck_over_ranks<3>(deck, *args, deck_name, ck);
      else
        run_deck_over_ranks<2>(deck, *args, deck_name, ck);
      return;
    }
#endif
    if (deck_dimension(deck) == 3)
      run_deck<3>(deck, *args, deck_name, ck);
    else
      run_deck<2>(deck, *args, deck_name, ck);
  });

  auto check_file = std::make_shared<std::string>();
  auto check_set = std::make_shared<std::vector<std::string>>();
  auto* check =
      app.add_subcommand("check", "Validate a run deck or a study deck (every run's deck) without running it");
  check->add_option("deck", *check_file, "TOML deck")->required()->check(CLI::ExistingFile);
  check->add_option("--set", *check_set,
                    "override a key, KEY=VALUE in TOML, as pbxmpm run --set or pbxmpm study --set would");
  check->callback([check_file, check_set] {
    // a study deck is checked as `pbxmpm study` checks it before its first run: every run's deck
    // built, every specimen packed
    if (Deck::from_file(*check_file).root().has("study")) {
      StudySpec s = read_study(*check_file);
      apply_set_options(s, *check_set);  // as `pbxmpm study ... --set` would run it
      const int n = check_study(s);
      std::printf("%s: valid study '%s': %d runs over base deck %s, every run deck builds\n", check_file->c_str(),
                  s.name.c_str(), n, s.base_deck.c_str());
      return;
    }
    Deck deck = check_set->empty() ? Deck::from_file(*check_file) : deck_from_file_with(*check_file, *check_set);
    if (deck_dimension(deck) == 3)
      check_deck<3>(*check_file, deck);
    else
      check_deck<2>(*check_file, deck);
  });
}

}  // namespace pbx::app
