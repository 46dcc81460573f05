// `pbxmpm run DECK` and `pbxmpm check DECK`.
#include <cstdio>

#include <CLI/CLI.hpp>
#include <fmt/format.h>

#include "app/commands.hpp"
#include "core/error.hpp"
#include "io/deck.hpp"
#include <filesystem>

#include "io/checkpoint.hpp"
#include "solver/runner.hpp"
#include "study/study.hpp"

namespace pbx::app {

namespace {

struct RunArgs {
  std::string deck, out = "out/run", restart;
  int threads = 0, checkpoint_every = 0;
  double checkpoint_minutes = 10;
  bool quiet = false;
};


Scene<2> load(const std::string& file, Deck& deck) {
  deck = Deck::from_file(file);
  Scene<2> scene = build_scene<2>(deck);
  deck.check_unused();
  return scene;
}

}  // namespace

void register_run(CLI::App& app) {
  auto args = std::make_shared<RunArgs>();
  auto* run = app.add_subcommand("run", "Run the simulation a deck describes");
  run->add_option("deck", args->deck, "TOML deck (not needed with --restart)")->check(CLI::ExistingFile);
  run->add_option("--out,-o", args->out, "output directory (history.csv, run.json, snapshots/)");
  run->add_option("--checkpoint-every", args->checkpoint_every,
                  "write OUT/checkpoint.h5 every N history rows (it is overwritten each time)")
      ->check(CLI::Range(1, 1000000));
  run->add_option("--checkpoint-minutes", args->checkpoint_minutes,
                  "also write OUT/checkpoint.h5 at the first history row after this many minutes since the last one "
                  "(0: never)")
      ->check(CLI::Range(0.0, 1e6))
      ->capture_default_str();
  run->add_option("--restart", args->restart,
                  "continue the run saved in this checkpoint, in the checkpoint's folder (its deck, its history.csv)")
      ->check(CLI::ExistingFile);
  run->add_option("--threads,-t", args->threads, "OpenMP threads (default: OMP_NUM_THREADS, else one per 50,000 particles up to the cores)")->check(CLI::Range(1, 1024));
  run->add_flag("--quiet,-q", args->quiet, "no progress display");
  run->callback([args, run] {
    if (args->out.empty())
      throw InputError("--out: an empty folder name (an unset shell variable?); give the output folder");
    Deck deck = Deck::from_string("", "");
    CheckpointData ck;
    std::string deck_name = args->deck;
    if (!args->restart.empty()) {
      // the checkpoint carries its deck: a deck given beside it would be ignored, and an edited one
      // taken for the one in effect
      if (!args->deck.empty())
        throw InputError(fmt::format("pbxmpm run: give a deck or --restart CHECKPOINT, not both (the run continues "
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
          throw InputError(fmt::format("pbxmpm run: --restart continues the run in the checkpoint's own folder '{}'; "
                                       "--out '{}' is another folder (copy the whole run folder to continue it "
                                       "elsewhere)",
                                       folder, args->out));
      }
      args->out = folder;
    } else if (args->deck.empty()) {
      throw InputError("pbxmpm run: give a deck, or --restart CHECKPOINT");
    } else {
      deck = Deck::from_file(args->deck);
    }
    Scene<2> scene = build_scene<2>(deck);
    deck.check_unused();
    RunOptions opt;
    opt.out_dir = args->out;
    opt.threads = args->threads;
    opt.progress = !args->quiet;
    opt.deck_json = deck.to_json();
    opt.deck_text = deck.text();
    opt.deck_name = deck_name;
    opt.checkpoint_every = args->checkpoint_every;
    opt.checkpoint_wall_s = 60.0 * args->checkpoint_minutes;
    Runner<2> runner(scene, opt, !args->restart.empty());
    if (!args->restart.empty()) runner.resume(ck);
    std::fprintf(stderr, "pbxmpm: %s%s: %zu particles, %ld x %ld nodes, %d fields, end time %.4g s -> %s\n",
                 args->restart.empty() ? "" : "restart of ", deck_name.c_str(), scene.particles.size(), scene.grid.n[0], scene.grid.n[1], scene.grid.fields,
                 scene.control.end_time, args->out.c_str());
    runner.run();
  });

  auto check_file = std::make_shared<std::string>();
  auto* check = app.add_subcommand("check", "Validate a run deck or a study deck (every run's deck) without running it");
  check->add_option("deck", *check_file, "TOML deck")->required()->check(CLI::ExistingFile);
  check->callback([check_file] {
    // a study deck is checked as `pbxmpm study` checks it before its first run: every run's deck
    // built, every specimen packed
    if (Deck::from_file(*check_file).root().has("study")) {
      const StudySpec s = read_study(*check_file);
      const int n = check_study(s);
      std::printf("%s: valid study '%s': %d runs over base deck %s, every run deck builds\n", check_file->c_str(),
                  s.name.c_str(), n, s.base_deck.c_str());
      return;
    }
    Deck deck = Deck::from_string("", "");
    Scene<2> scene = load(*check_file, deck);
    std::printf("%s: valid. %zu particles in %zu materials, %d deformable fields, %zu rigid bodies, "
                "grid %ld x %ld nodes (h = %.4g m), end time %.4g s\n",
                check_file->c_str(), scene.particles.size(), scene.materials.size(), scene.deformable_fields,
                scene.bodies.size(), scene.grid.n[0], scene.grid.n[1], scene.grid.h, scene.control.end_time);
  });
}

}  // namespace pbx::app
