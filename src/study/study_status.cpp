#include "study/study_status.hpp"

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <sstream>

#include <fmt/format.h>
#include <signal.h>
#include <unistd.h>

#include "io/json.hpp"
#include "core/error.hpp"
#include "io/checkpoint.hpp"
#include "run/runner.hpp"

namespace fs = std::filesystem;

namespace pbx {

namespace {

// The "strain" value of the last row of history.csv; -1 when there is none.
double last_strain(const fs::path& file) {
  std::ifstream in(file);
  std::string header, line, last;
  if (!std::getline(in, header)) return -1;
  auto split = [](const std::string& text) {
    std::vector<std::string> cells;
    std::stringstream ss(text);
    for (std::string c; std::getline(ss, c, ',');) cells.push_back(c);
    return cells;
  };
  const auto names = split(header);
  const auto col = std::find(names.begin(), names.end(), "strain") - names.begin();
  while (std::getline(in, line))
    if (!line.empty()) last = line;
  const auto cells = split(last);
  if (col >= static_cast<long>(names.size()) || col >= static_cast<long>(cells.size())) return -1;
  try {
    return std::stod(cells[static_cast<std::size_t>(col)]);
  } catch (const std::exception&) {
    return -1;
  }
}

double age_s(const fs::path& file) {
  const auto dt = fs::file_time_type::clock::now() - fs::last_write_time(file);
  return std::chrono::duration<double>(dt).count();
}

std::string ago(double s) {
  if (s < 0) return "-";
  if (s < 120) return fmt::format("{:.0f} s ago", s);
  if (s < 7200) return fmt::format("{:.0f} min ago", s / 60);
  return fmt::format("{:.1f} h ago", s / 3600);
}

}  // namespace

std::vector<RunStatus> study_status(const std::string& study_dir) {
  const fs::path dir(study_dir);
  if (!fs::exists(dir / "study.json"))
    throw InputError(fmt::format("{}: no study.json (a study directory is made by 'pbxmpm study')", study_dir));
  const Json study = json_read_file((dir / "study.json").string());
  const Json* runs = json_find(study, "runs");
  if (!runs || !runs->is_array()) throw InputError(fmt::format("{}/study.json: no \"runs\" array", study_dir));
  std::vector<RunStatus> out;
  for (const auto& e : json_array(*runs)) {
    RunStatus r;
    const Json* id = json_find(e, "id");
    if (!id || !id->is_string()) throw InputError(fmt::format("{}/study.json: a run without \"id\"", study_dir));
    r.id = json_string(*id);
    const fs::path rd = dir / "runs" / r.id;
    r.state = "not started";
    if (fs::exists(rd / "run.json")) {
      try {
        const Json rj = json_read_file((rd / "run.json").string());
        const Json* st = json_find(rj, "status");
        const std::string status = st && st->is_string() ? json_string(*st) : "unknown";
        r.state = status == "finished" ? (fs::exists(rd / "analysis.json") ? "finished" : "finished, not analysed")
                  : status == "failed" ? "failed"
                                       : "started";
        const Json* host = json_find(rj, "host");
        const Json* pid = json_find(rj, "pid");
        if (r.state == "started" && host && host->is_string() && pid && pid->is_number()) {
          if (json_string(*host) == host_name()) {
            const auto p = static_cast<pid_t>(json_number(*pid));
            r.state = p > 0 && (::kill(p, 0) == 0 || errno == EPERM) ? "running" : "interrupted";
            if (r.state == "running") r.message = fmt::format("pid {}", p);
          } else {
            r.message = "on " + json_string(*host);
          }
        }
        if (const Json* m = json_find(rj, "message"); m && m->is_string()) r.message = json_string(*m);
        if (const Json* v = json_find(rj, "code_version"); v && v->is_string()) r.code_version = json_string(*v);
        if (const Json* es = json_find(rj, "end_strain"); es && es->is_number()) r.end_strain = json_number(*es);
      } catch (const std::exception& ex) {
        r.state = "started";
        r.message = ex.what();
      }
    }
    if (fs::exists(rd / "history.csv")) {
      r.strain = last_strain(rd / "history.csv");
      r.last_row_age_s = age_s(rd / "history.csv");
    }
    if (fs::exists(rd / "checkpoint.h5")) {
      try {
        const CheckpointData c = read_checkpoint_header((rd / "checkpoint.h5").string());
        r.checkpoint_step = static_cast<long>(c.scalars.count("steps") ? c.scalars.at("steps") : -1);
      } catch (const std::exception& ex) {
        r.message += (r.message.empty() ? "" : "; ") + std::string("checkpoint unreadable: ") + ex.what();
      }
    }
    out.push_back(std::move(r));
  }
  return out;
}

namespace {
// The study deck study.json records (studies written before 2026-12-05 do not: a placeholder).
std::string study_deck(const std::string& study_dir) {
  try {
    const Json study = json_read_file((fs::path(study_dir) / "study.json").string());
    const Json* deck = json_find(study, "deck");
    if (deck && deck->is_string()) return json_string(*deck);
  } catch (const std::exception&) {
  }
  return "<study deck>";
}
}  // namespace

std::string format_study_status(const std::vector<RunStatus>& runs, const std::string& study_dir) {
  std::string s = fmt::format("{:<28} {:<22} {:>16} {:>14} {:>12}  {}\n", "run", "state", "strain reached", "last row",
                              "checkpoint", "note");
  std::string todo;
  int finished = 0;
  for (const auto& r : runs) {
    const std::string strain = r.strain < 0       ? "-"
                               : r.end_strain > 0 ? fmt::format("{:.3f} / {:.2f} %", 100 * r.strain, 100 * r.end_strain)
                                                  : fmt::format("{:.3f} %", 100 * r.strain);
    const std::string ck = r.checkpoint_step < 0 ? "-" : fmt::format("step {}", r.checkpoint_step);
    std::string note = r.state == "started" ? "running, or interrupted if the last row is old" : r.message;
    if (r.state == "interrupted") note = "its process is gone: rerun the study to continue it";
    if (r.state == "started" && !r.message.empty()) note = r.message + "; " + note;
    if (r.state == "finished") note = r.code_version;
    s +=
        fmt::format("{:<28} {:<22} {:>16} {:>14} {:>12}  {}\n", r.id, r.state, strain, ago(r.last_row_age_s), ck, note);
    if (r.state == "finished")
      ++finished;
    else
      todo += (todo.empty() ? "" : ",") + r.id;
  }
  s += fmt::format("{} of {} runs finished", finished, runs.size());
  if (!todo.empty())
    s += fmt::format("; the others: pbxmpm study {} --out {} --only {} (with the study's --set options, if it had any)",
                     study_deck(study_dir), study_dir, todo);
  return s + "\n";
}

}  // namespace pbx
