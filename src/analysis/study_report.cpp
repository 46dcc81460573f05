#include "analysis/study_report.hpp"

#include <cstdlib>
#include <filesystem>
#include <stdexcept>

#include <sys/wait.h>

#include <fmt/format.h>

#include "analysis/report_files.hpp"
#include "core/error.hpp"

namespace fs = std::filesystem;

namespace pbx {

namespace {
// Single-quote for the POSIX shell used by std::system.
std::string quoted(const std::string& s) {
  std::string q = "'";
  for (char c : s) q += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return q + "'";
}
}  // namespace

std::string build_report(const std::string& study_dir, const ReportOptions& opt) {
  std::vector<MissingRun> missing;
  const std::vector<StudyRun> runs = load_study(study_dir, opt.fits, &missing);
  Json fits = fit_study(runs, opt.fits);
  if (!missing.empty()) fits["missing_runs"] = missing_runs_json(missing);
  const fs::path out = opt.out_dir.empty() ? fs::path(study_dir) / "report" : fs::path(opt.out_dir);
  fs::create_directories(out);
  json_write_file((out / "fits.json").string(), fits);

  const std::string script = opt.script.empty() ? report_file("make_report.py") : opt.script;
  if (!fs::exists(script)) throw InputError(fmt::format("report script '{}' not found", script));
  if (!fs::exists(opt.python)) {
    throw InputError(fmt::format(
        "python '{}' not found (install python3-numpy python3-matplotlib: scripts/install-deps)", opt.python));
  }
  const std::string paper = opt.fits.paper_values.empty() ? default_paper_values_path() : opt.fits.paper_values;
  const std::string cmd = fmt::format("{} {} {} --out {} --paper-values {}", quoted(opt.python), quoted(script),
                                      quoted(study_dir), quoted(out.string()), quoted(paper));
  const int rc = std::system(cmd.c_str());
  if (rc != 0) {
    // std::system returns a wait status (256 for exit code 1): say what it means
    const std::string how = rc == -1          ? "could not be started"
                            : WIFEXITED(rc)   ? fmt::format("exited with code {}", WEXITSTATUS(rc))
                            : WIFSIGNALED(rc) ? fmt::format("was killed by signal {}", WTERMSIG(rc))
                                              : fmt::format("ended with status {}", rc);
    throw std::runtime_error(fmt::format("the report script {} (its messages are above): {}", how, cmd));
  }
  return out.string();
}

}  // namespace pbx
