// pbxmpm: mesoscale MPM for polymer-bonded explosives. See README.md.
#include <cstdio>
#include <exception>
#include <filesystem>
#include <new>

#include <CLI/CLI.hpp>

#include "app/commands.hpp"
#include "core/error.hpp"
#include "pbxmpm_git.hpp"  // PBXMPM_GIT, generated at build time

#ifdef PBXMPM_HAVE_MPI
#include <mpi.h>
#endif

int main(int argc, char** argv) {
  CLI::App app{"pbxmpm " PBXMPM_VERSION " (" PBXMPM_GIT
               "): material point method for the mesoscale mechanics of polymer-bonded explosives"};
  app.require_subcommand(1);
  app.option_defaults()->always_capture_default();  // --help shows every option's default
  app.set_version_flag("--version", "pbxmpm " PBXMPM_VERSION " (" PBXMPM_GIT ")");
  pbx::app::register_run(app);
  pbx::app::register_material(app);
  pbx::app::register_pack(app);
  pbx::app::register_analysis(app);
  pbx::app::register_study(app);
  // A misspelt command would otherwise be reported as "A subcommand is required".
  // The same one level down (pbxmpm fit foo) when the command takes sub-commands.
  CLI::App* parent = &app;
  std::string path = "pbxmpm";
  for (int level = 1; level <= 2 && argc > level && argv[level][0] != '-'; ++level) {
    const auto subs = parent->get_subcommands([](CLI::App*) { return true; });
    if (subs.empty()) break;
    std::string names;
    CLI::App* found = nullptr;
    for (CLI::App* sub : subs) {
      if (sub->get_name() == argv[level]) found = sub;
      names += (names.empty() ? "" : ", ") + sub->get_name();
    }
    if (!found) {
      std::fprintf(stderr, "%s: unknown command '%s' (the commands: %s; see %s --help)\n", path.c_str(), argv[level],
                   names.c_str(), path.c_str());
      return 2;
    }
    path += std::string(" ") + argv[level];
    parent = found;
  }
  // Exit codes (README, "Exit codes"): 0 done, 1 other error, 2 bad input or usage, 3 run stopped
  // unstable, 4 an output file could not be written, 130 interrupted (a checkpoint was saved).
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e) == 0 ? 0 : 2;  // CLI11's own codes (105, 106, ...) are usage errors
  } catch (const pbx::InputError& e) {
    std::fprintf(stderr, "pbxmpm: input error: %s\n", e.what());
    return 2;
  } catch (const pbx::InstabilityError& e) {
    std::fprintf(stderr, "pbxmpm: run stopped, unstable: %s\n", e.what());
    return 3;
  } catch (const pbx::OutputError& e) {
    std::fprintf(stderr, "pbxmpm: output error: %s\n", e.what());
    return 4;
  } catch (const pbx::Interrupted& e) {
    std::fprintf(stderr, "pbxmpm: %s\n", e.what());
    return 130;
  } catch (const std::filesystem::filesystem_error& e) {
    std::fprintf(stderr,
                 "pbxmpm: error: file system error on '%s': %s (for an output folder: check --out and "
                 "its permissions)\n",
                 e.path1().string().c_str(), e.code().message().c_str());
    return 1;
  } catch (const std::bad_alloc&) {
    std::fprintf(stderr,
                 "pbxmpm: error: out of memory: the deck asks for more particles, grid or grains than this "
                 "machine can hold (check the sizes, grid.cell_size and particles_per_cell)\n");
    return 1;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "pbxmpm: error: %s\n", e.what());
    return 1;
  }
  return 0;
}
