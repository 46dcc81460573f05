#pragma once
// `pbxmpm status STUDY_DIR`: where each run of a study stands, from its files alone (no run is
// touched): finished, failed, in progress or interrupted (strain reached, last history row, last
// checkpoint), or not started. For studies that take several sittings.
#include <string>
#include <vector>

namespace pbx {

struct RunStatus {
  std::string id;
  // "finished", "failed", "running" (its process is alive on this machine), "interrupted" (it is
  // not), "started" (on another machine, or by a version that did not record its process), "not started"
  std::string state;
  double strain = -1;          // strain of the last history row (-1: none)
  double end_strain = -1;      // the run's end strain from run.json (-1: unknown)
  double last_row_age_s = -1;  // seconds since history.csv was last written (-1: none)
  long checkpoint_step = -1;   // step of the checkpoint (-1: none)
  double checkpoint_strain = -1;
  std::string code_version, message;
};

// Throws InputError when STUDY_DIR has no study.json.
std::vector<RunStatus> study_status(const std::string& study_dir);

// The table `pbxmpm status` prints, with a last line naming the runs still to do.
std::string format_study_status(const std::vector<RunStatus>& runs, const std::string& study_dir);

}  // namespace pbx
