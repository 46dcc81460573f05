// What a run tells its user while and after it runs: run.json (status, settings, wall time per
// stage, memory, versions) and the progress line.
#include "run/runner.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <filesystem>

#include <fmt/format.h>

#include "io/json.hpp"

#include <omp.h>
#include <unistd.h>

#include "pbxmpm_git.hpp"  // PBXMPM_GIT, generated at build time
#include "run/wall_clock.hpp"

namespace pbx {

template <int D>
std::string Runner<D>::this_and_earlier_versions() const {
  const std::string now = fmt::format("{} ({})", PBXMPM_VERSION, PBXMPM_GIT);
  return code_versions_.empty() ? now : code_versions_ + "; " + now;
}

template <int D>
void Runner<D>::write_run_json(const std::string& status, const std::string& message) const {
  if (!writer_) return;
  // one reading of the clock for the wall time and its split into stages, so that they add up
  // exactly (a second reading after building the rest of run.json made them disagree by 5 ms on a
  // loaded machine)
  const double now = now_s();
  const double wall = wall_before_ + now - wall_start_;
  const double steps = static_cast<double>(solver_.step_count() - steps_unclocked_);
  const double mass = whole_.mass, vol = whole_.volume0;
  Json specimen;  // null without a die
  if (sc_.die) {
    const double box = sc_.die->volume();
    specimen = {{"density_kg_m3", mass / box},
                {"porosity", 1.0 - vol / box},
                {"tmd_kg_m3", mass / vol},
                {"width_m", sc_.die->width},
                {"height_m", sc_.die->height}};
    if (sc_.die->depth > 0) specimen["depth_m"] = sc_.die->depth;
    if (sc_.packing_stats) {  // the packed geometry's porosity, which the particles rasterise
      specimen["packing_porosity"] = sc_.packing_stats->porosity;
      specimen["colours"] = sc_.packing_stats->colours;
    }
    // film = "bonds" (one process only, so these are the whole specimen's): how much film the pairs
    // carry, the quantity that sets the specimen's stiffness when the binder is counted once
    // (docs/theory/paper_study.md, "Where the density trend comes from")
    if (const auto& bonds = sc_.layer_data.bonds; !bonds.empty()) {
      double coef = 0;
      for (const auto& b : bonds) coef += b.coef;
      specimen["film_pairs"] = bonds.size();
      specimen["film_pairs_sum_a_over_t"] = coef;  // sum over pairs of a / (2 (t + g)); 2-D: m per m of depth
    }
    // gap_binder = "join" (film = "bonds", or "integrated" with the option)
    if (!sc_.layer_data.bonds.empty() || sc_.layer_data.gap_particles_joined > 0)
      specimen["film_gap_binder_particles_joined"] = sc_.layer_data.gap_particles_joined;
  }
  Json mats = Json::array();
  for (std::size_t m = 0; m < sc_.materials.size(); ++m)
    mats.push_back({{"name", sc_.material_names[m]},
                    {"model", sc_.materials[m]->model()},
                    {"density_kg_m3", sc_.materials[m]->density()},
                    {"particles", whole_.by_material[m]}});
  std::size_t rigid = 0;
  for (auto& b : sc_.bodies) rigid += b.x.size();
  // rounded where more digits would only be noise (wall clock, memory)
  // (x * 10^d rounded, then divided: the nearest double to the decimal, which prints short)
  auto rounded = [](double x, int decimals) {
    const double scale = std::pow(10.0, decimals);
    return std::round(x * scale) / scale;
  };
  Json j;
  j["status"] = status;
  j["message"] = message;
  j["run_id"] = run_id_;
  j["code_version"] = fmt::format("{} ({})", PBXMPM_VERSION, PBXMPM_GIT);
  j["segment_code_versions"] = this_and_earlier_versions();
  j["host"] = host_name();
  j["pid"] = static_cast<long>(::getpid());
  j["dimension"] = D;
  j["threads"] = omp_get_max_threads();
  j["threads_chosen_by"] = threads_.chosen_by;
  j["particles"] = whole_.particles;
  j["mpi_ranks"] = opt_.ranks;
  j["rigid_particles"] = rigid;
  j["grid_nodes"] = sc_.grid.nodes();
  j["fields"] = sc_.grid.fields;
  j["steps"] = solver_.step_count();
  j["time_s"] = solver_.time();
  j["wall_time_s"] = rounded(wall, 4);
  j["restarts"] = restarts_;
  j["particle_updates_per_s"] = wall > 0 ? rounded(static_cast<double>(whole_.particles) * steps / wall, 0) : 0.0;
  j["peak_memory_MB"] = rounded(peak_memory_mb(), 1);  // of rank 0 in a run over several ranks
  {
    // where this segment's wall time went: the step's stages (solver/stage_clock.hpp), and the
    // rest of the run (history rows, field overlap, snapshots, checkpoints, progress)
    const StageClock& c = solver_.stage_clock();
    Json stages;
    for (std::size_t s = 0; s < kStageNames.size(); ++s)
      stages[kStageNames[s]] = rounded(c.seconds(static_cast<Stage>(s)), 4);
    stages["outside_steps"] = rounded(std::max(0.0, now - wall_start_ - c.total()), 4);
    j["stage_wall_s"] = stages;
  }
  j["field_overlap_pixel_m"] = overlap_ ? Json(overlap_->pixel()) : Json();
  j["temperature_K"] = sc_.control.temperature;
  j["mass_scaling"] = sc_.settings.mass_scaling;
  j["ramp_strain"] = sc_.die ? sc_.die->ramp_strain : 0.0;
  j["punch_velocity_m_s"] = sc_.die ? Json(sc_.die->punch_velocity) : Json();
  j["end_strain"] = sc_.control.end_strain;
  j["specimen"] = specimen;
  j["study"] = opt_.study;
  j["materials"] = mats;
  j["units"] = D == 2 ? "SI; 2-D (plane strain): forces, energies, masses and momenta per metre of depth" : "SI; 3-D";
  j["deck"] = opt_.deck;
  json_write_file((std::filesystem::path(opt_.out_dir) / "run.json").string(), j);
}

// The machine a run goes on (`pbxmpm status` tells a live run from an interrupted one by it and
// the pid).
std::string host_name() {
  char name[256] = {};
  if (gethostname(name, sizeof name - 1) != 0) return "unknown";
  std::string h(name);
  for (char& c : h)
    if (c == '"' || c == '\\' || static_cast<unsigned char>(c) < 0x20) c = '_';
  return h;
}

double study_eta_s(double wall_s, double frac, double frac_at_start, int runs_after) {
  if (!(frac > frac_at_start) || !(wall_s > 0)) return -1;
  const double whole_run = wall_s / (frac - frac_at_start);
  return whole_run * (1.0 - frac) + runs_after * whole_run;
}

template <int D>
void Runner<D>::report_progress(const Measurement& m, bool final) {
  if (!opt_.progress) return;
  const double frac = std::min(1.0, m.t / sc_.control.end_time);
  const double wall = now_s() - wall_start_;
  const double rate = wall > 0 ? static_cast<double>(solver_.step_count() - steps_at_start_) / wall : 0;
  const double eta = study_eta_s(wall, frac, frac_at_start_, 0);
  const std::string study = opt_.progress_label.empty()
                                ? std::string()
                                : fmt::format("  ({}, study ETA {})", opt_.progress_label,
                                              hms(study_eta_s(wall, frac, frac_at_start_, opt_.runs_after)));
  // the punch's strain and stress with a die; the time otherwise (no punch to report)
  const std::string load = sc_.die
                               ? fmt::format("strain {:6.3f}%  punch {:8.3f} MPa", 100 * m.strain, m.punch_stress / 1e6)
                               : fmt::format("t {:.4g} s  KE/IE {:.3g}", m.t, m.ke_ie);
  if (tty_) {
    const int width = 30, fill = static_cast<int>(frac * width);
    std::fprintf(stderr, "\r[%s%s] %5.1f%%  %s  %7.0f steps/s  ETA %s%s%s",
                 std::string(static_cast<std::size_t>(fill), '#').c_str(),
                 std::string(static_cast<std::size_t>(width - fill), ' ').c_str(), 100 * frac, load.c_str(), rate,
                 hms(eta).c_str(), study.c_str(), final ? "\n" : "");
    std::fflush(stderr);
  } else if (final || frac - last_progress_ >= 0.1 || wall - last_progress_wall_ >= 60.0) {
    // every 10 % or every minute, whichever comes first: a multi-hour run in a log file (no
    // terminal) must still show it is alive
    last_progress_ = frac;
    last_progress_wall_ = wall;
    if (sc_.die)
      std::fprintf(
          stderr, "pbxmpm: %5.1f%%  t %.4g s  strain %.4f%%  punch %.4g MPa  KE/IE %.3g  %.0f steps/s  ETA %s%s\n",
          100 * frac, m.t, 100 * m.strain, m.punch_stress / 1e6, m.ke_ie, rate, hms(eta).c_str(), study.c_str());
    else
      std::fprintf(stderr, "pbxmpm: %5.1f%%  t %.4g s  KE/IE %.3g  %.0f steps/s  ETA %s%s\n", 100 * frac, m.t, m.ke_ie,
                   rate, hms(eta).c_str(), study.c_str());
  }
}

template std::string Runner<2>::this_and_earlier_versions() const;
template void Runner<2>::write_run_json(const std::string&, const std::string&) const;
template void Runner<2>::report_progress(const Measurement&, bool);
template std::string Runner<3>::this_and_earlier_versions() const;
template void Runner<3>::write_run_json(const std::string&, const std::string&) const;
template void Runner<3>::report_progress(const Measurement&, bool);

}  // namespace pbx
