// `pbxmpm study DECK`: the paper study (or any sweep) end to end.
#include <cstdio>
#include <stdexcept>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>
#include <fmt/format.h>

#include "app/commands.hpp"
#include "core/error.hpp"
#include "io/deck_override.hpp"
#include "study/study.hpp"
#include "study/study_status.hpp"

namespace pbx::app {

void register_study(CLI::App& app) {
  struct Args {
    std::string deck, out;
    std::vector<std::string> only, set;
    int threads = 0, checkpoint_every = 10;
    bool no_report = false, quiet = false;
  };
  auto a = std::make_shared<Args>();
  auto* st =
      app.add_subcommand("study", "Run a study deck (runs x seeds, MPI-aware, resumable), analyse, fit and report");
  st->add_option("deck", a->deck, "study deck (TOML with a [study] table)")->required()->check(CLI::ExistingFile);
  st->add_option("--out,-o", a->out, "study directory (default: out/<study name>)");
  st->add_option(
        "--threads,-t", a->threads,
        "OpenMP threads per run (default: OMP_NUM_THREADS, else one per 50,000 particles up to the cores of this rank)")
      ->check(CLI::Range(1, 1024))
      ->default_str("auto");
  st->add_option("--only", a->only,
                 "run only these run ids (comma-separated, as in STUDY/study.json); the report waits until every run "
                 "has finished")
      ->delimiter(',');
  st->add_option("--checkpoint-every", a->checkpoint_every,
                 "each run writes runs/<id>/checkpoint.h5 every N history rows (0: never); an interrupted run "
                 "continues from it when the study is started again")
      ->check(CLI::Range(0, 1000000))
      ->capture_default_str();
  st->add_option(
      "--set", a->set,
      "override a key of every run deck, KEY=VALUE in TOML (after [study.set]; a key a group varies is refused); "
      "repeatable");
  st->add_flag("--no-report", a->no_report, "skip the report at the end");
  st->add_flag("--quiet,-q", a->quiet, "no per-run progress display");
  st->callback([a, st] {
    if (st->count("--out") > 0 && a->out.empty())
      throw InputError(
          "--out: an empty folder name (an unset shell variable?); give a folder, or leave --out out for out/<study "
          "name>");
    StudySpec s = read_study(a->deck);
    apply_set_options(s, a->set);
    StudyOptions o;
    if (a->out.empty() && !is_folder_name(s.name))
      throw InputError(
          fmt::format("study.name '{}' would name the default output folder out/<name>: give --out, or "
                      "a name of letters, digits, '_', '-' and '.'",
                      s.name));
    o.out_dir = a->out.empty() ? "out/" + s.name : a->out;
    o.threads = a->threads;
    o.report = !a->no_report;
    o.progress = !a->quiet;
    o.only = a->only;
    o.checkpoint_every = a->checkpoint_every;
    const int failed = run_study(s, o);
    if (failed == kStudyInterrupted)
      throw Interrupted(
          "study interrupted; run the same command again to continue it from the interrupted run's checkpoint");
    if (failed == kStudyNotStarted)
      throw InputError("the study did not start (no run was made): see the messages above");
    if (failed > 0)
      throw std::runtime_error(
          fmt::format("{} of the study failed; see the messages above (a failed run's run.json holds its message)",
                      failed == 1 ? std::string("1 run") : fmt::format("{} runs", failed)));
  });

  auto dir = std::make_shared<std::string>();
  auto* status =
      app.add_subcommand("status", "Where each run of a study stands (finished, started, checkpoint, not started)");
  status->add_option("STUDY_DIR", *dir, "study directory (study.json, runs/<id>/)")->required();
  status->callback([dir] { std::fputs(format_study_status(study_status(*dir), *dir).c_str(), stdout); });
}

}  // namespace pbx::app
