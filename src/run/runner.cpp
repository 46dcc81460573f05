#include "run/runner.hpp"

#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <cstdio>
#include <atomic>
#include <csignal>
#include <filesystem>
#include <fstream>
#include <random>

#include <fmt/format.h>

#include "io/atomic_write.hpp"
#include "io/json.hpp"
#include <omp.h>
#include <sys/resource.h>
#include <unistd.h>

#include "core/error.hpp"
#include "core/parallel.hpp"
#include "pbxmpm_git.hpp"  // PBXMPM_GIT, generated at build time

namespace pbx {

namespace {
double now_s() {
  using namespace std::chrono;
  return duration<double>(steady_clock::now().time_since_epoch()).count();
}
double peak_memory_mb() {
  rusage ru{};
  getrusage(RUSAGE_SELF, &ru);
  return static_cast<double>(ru.ru_maxrss) / 1024.0;
}
// A fresh run's identity: run.json and every checkpoint carry it, so that a restart refuses a
// folder holding another run.
std::string new_run_id() {
  std::random_device rd;
  return fmt::format("{:08x}{:08x}", rd(), rd());
}

// The run_id a folder's run.json records, or "" (no run.json, or one written before 2026-12-04).
std::string run_id_in(const std::filesystem::path& dir) {
  if (!std::filesystem::exists(dir / "run.json")) return "";
  const Json run = json_read_file((dir / "run.json").string());
  const Json* id = json_find(run, "run_id");
  return id && id->is_string() ? id->get<std::string>() : std::string();
}

// SIGINT/SIGTERM: the first asks the run to stop at its next history row (after a checkpoint),
// a second one stops the process at once with the signal's default action.
std::atomic<int> g_stop_signal{0};
extern "C" void on_stop_signal(int sig) {
  if (g_stop_signal.load() != 0) {
    std::signal(sig, SIG_DFL);
    std::raise(sig);
    return;
  }
  g_stop_signal.store(sig);
}
}  // namespace

bool stop_signal_received() { return g_stop_signal.load() != 0; }

namespace {
class StopSignals {
 public:
  explicit StopSignals(bool on) : on_(on) {
    if (!on_) return;
    g_stop_signal.store(0);
    struct sigaction sa {};
    sa.sa_handler = on_stop_signal;
    sigemptyset(&sa.sa_mask);
    sigaction(SIGINT, &sa, &old_int_);
    sigaction(SIGTERM, &sa, &old_term_);
  }
  ~StopSignals() {
    if (!on_) return;
    sigaction(SIGINT, &old_int_, nullptr);
    sigaction(SIGTERM, &old_term_, nullptr);
  }
  StopSignals(const StopSignals&) = delete;
  StopSignals& operator=(const StopSignals&) = delete;

 private:
  bool on_;
  struct sigaction old_int_ {
  }, old_term_{};
};

std::string hms(double s) {
  if (!(s >= 0) || s > 1e7) return "--:--:--";
  const long t = std::lround(s);
  return fmt::format("{:02d}:{:02d}:{:02d}", t / 3600, (t / 60) % 60, t % 60);
}
}  // namespace

template <int D>
Runner<D>::Runner(Scene<D>& scene, RunOptions opt, bool restart) : sc_(scene), opt_(std::move(opt)), solver_(scene) {
  threads_ = choose_threads(opt_.threads, sc_.particles.size());
  omp_set_num_threads(threads_.threads);
  if (!threads_.note.empty()) std::fprintf(stderr, "pbxmpm: note: %s\n", threads_.note.c_str());
  tty_ = isatty(STDERR_FILENO);
  const char* axes = "xyz";
  // 2-D forces, energies, masses and momenta are per metre of depth (plane strain); 3-D ones are totals
  const std::string per = D == 2 ? "_per_m" : "";
  columns_ = {"step",
              "t_s",
              "dt_s",
              "strain",
              "punch_velocity_m_s",
              "punch_force_N" + per,
              "punch_stress_Pa",
              "wall_left_force_N" + per,
              "wall_right_force_N" + per,
              "wall_bottom_force_N" + per,
              "wall_stress_Pa",
              "sxx_Pa",
              "syy_Pa",
              "szz_Pa",
              "sxy_Pa",
              "kinetic_J" + per,
              "internal_J" + per,
              "dissipated_J" + per,
              "punch_work_J" + per,
              "ke_ie",
              "mass_kg" + per};
  for (int d = 0; d < D; ++d) columns_.push_back(fmt::format("momentum_{}_N_s{}", axes[d], per));
  for (int d = 0; d < D; ++d) columns_.push_back(fmt::format("com_v{}_m_s", axes[d]));
  for (auto& b : sc_.bodies)
    for (int d = 0; d < D; ++d) columns_.push_back(fmt::format("{}_f{}_N{}", b.name, axes[d], per));
  if (!sc_.contact.all_weld()) contact_pairs_ = contact_material_pairs(sc_.contact, sc_.material_names);
  for (auto& mp : contact_pairs_) {
    columns_.push_back(fmt::format("contact_{}_fn_N{}", mp.name, per));
    columns_.push_back(fmt::format("contact_{}_ft_N{}", mp.name, per));
    if (mp.first != mp.second)
      for (int d = 0; d < D; ++d) columns_.push_back(fmt::format("contact_{}_f{}_N{}", mp.name, axes[d], per));
  }
  if constexpr (D == 2) {
    if (sc_.deformable_fields > 1 && sc_.particles.size() > 0) {
      overlap_.emplace(sc_.grid, FieldOverlap::default_pixel(sc_.particles));
      columns_.push_back("field_overlap_m2_per_m");
    }
  }
  if (sc_.contact.has_layers()) columns_.push_back("layer_energy_J" + per);
  if (!opt_.out_dir.empty()) {
    lock_ = OutputLock(opt_.out_dir, "run");
    if (!restart) {
      clear_previous_run();
      run_id_ = new_run_id();
      history_ = CsvWriter((std::filesystem::path(opt_.out_dir) / "history.csv").string(), columns_);
    }
    snapshots_ = SnapshotWriter((std::filesystem::path(opt_.out_dir) / "snapshots").string());
  }
}

// A fresh run into a folder that holds an earlier run replaces it: the earlier run's files are
// removed first, so that none of them (its analysis.json, a checkpoint a later --restart would
// take, snapshots beyond this run's count) is read as this run's. Files pbxmpm does not write
// are left alone; a study's deck.toml is the study's, written before the run.
template <int D>
void Runner<D>::clear_previous_run() const {
  namespace fs = std::filesystem;
  const fs::path dir(opt_.out_dir);
  for (const char* f : {"run.json", "run.json.tmp", "history.csv", "analysis.json", "analysis.json.tmp",
                        "checkpoint.h5", "checkpoint.h5.tmp"})
    fs::remove(dir / f);
  const fs::path snaps = dir / "snapshots";
  if (fs::is_directory(snaps)) {
    std::vector<fs::path> old;
    for (const auto& e : fs::directory_iterator(snaps)) {
      const std::string n = e.path().filename().string();
      if ((n.rfind("snap_", 0) == 0 && (n.ends_with(".h5") || n.ends_with(".h5.tmp"))) || n == "snapshots.xmf" ||
          n == "snapshots.xmf.tmp")
        old.push_back(e.path());
    }
    for (const auto& f : old) fs::remove(f);
  }
}

template <int D>
Measurement Runner<D>::measure() {
  const auto& P = sc_.particles;
  Measurement m;
  const double t = solver_.time();
  m.t = t;
  m.dt = solver_.dt();
  const double span = t - t_last_row_;
  m.body_force.resize(sc_.bodies.size());
  for (std::size_t b = 0; b < sc_.bodies.size(); ++b) {
    const Vec<D> f = span > 0 ? Vec<D>(sc_.bodies[b].impulse / span) : Vec<D>::Zero();
    m.body_force[b].assign(f.data(), f.data() + D);
  }
  struct Sums {
    double vol = 0, mass = 0, ke = 0;
    Sym3 sv;
    Vec<D> p = Vec<D>::Zero();
    Sums& operator+=(const Sums& o) {
      vol += o.vol;
      mass += o.mass;
      ke += o.ke;
      sv += o.sv;
      p += o.p;
      return *this;
    }
  };
  const double fs = sc_.settings.mass_scaling;
  Sums s = ordered_reduce(static_cast<long>(P.size()), Sums{}, [&](long b, long e) {
    Sums r;
    for (long p = b; p < e; ++p) {
      r.vol += P.volume[p];
      r.mass += P.mass[p];
      r.ke += 0.5 * fs * P.mass[p] * P.v[p].squaredNorm();
      r.sv += P.volume[p] * P.stress[p];
      r.p += fs * P.mass[p] * P.v[p];
    }
    return r;
  });
  m.mass = s.mass;
  m.momentum.assign(s.p.data(), s.p.data() + D);
  const Vec<D> vcm = s.p / (fs * s.mass);
  m.com_velocity.assign(vcm.data(), vcm.data() + D);
  double box = s.vol;
  if (sc_.die) {
    const Die& die = *sc_.die;
    const auto& punch = sc_.bodies[die.punch];
    const double d = -punch.displacement_at(t)[1];
    m.strain = d / die.height;
    m.punch_velocity = -punch.velocity_at(t)[1];
    m.punch_force = -m.body_force[die.punch][1];
    m.punch_stress = m.punch_force / die.width;
    m.wall_left = m.body_force[die.left][0];
    m.wall_right = -m.body_force[die.right][0];
    m.wall_bottom = m.body_force[die.bottom][1];
    m.wall_stress = 0.5 * (m.wall_left + m.wall_right) / (die.height - d);
    box = die.width * (die.height - d);
  }
  m.mean_stress = (1.0 / box) * s.sv;
  m.kinetic = s.ke;
  m.internal = solver_.internal_energy();
  m.dissipated = solver_.dissipated_energy();
  for (auto& b : sc_.bodies) punch_work_ += b.work;
  m.punch_work = punch_work_;
  m.ke_ie = m.internal > 0 ? m.kinetic / m.internal : 0.0;
  for (auto& b : sc_.bodies) {
    b.impulse.setZero();
    b.work = 0;
  }
  auto& tally = solver_.contact_tally();
  for (auto& mp : contact_pairs_) {
    const PairImpulse<D> pi = material_pair_impulse<D>(tally, sc_.contact, mp);
    const double inv = span > 0 ? 1.0 / span : 0.0;
    std::vector<double> f = {pi.normal * inv, pi.shear * inv};
    if (mp.first != mp.second)
      for (int d = 0; d < D; ++d) f.push_back(pi.on_first[d] * inv);
    m.pair_force.push_back(std::move(f));
  }
  tally.clear();
  if constexpr (D == 2) {
    if (overlap_) m.field_overlap.push_back(overlap_->area(P));
  }
  if (sc_.contact.has_layers()) m.layer_energy.push_back(solver_.layer_energy());
  t_last_row_ = t;
  return m;
}

// "; particle p (material 'm') has a non-finite velocity" for the first particle whose state is
// not finite, or "" if every particle's is: names the culprit of a NaN found in the sums.
template <int D>
std::string Runner<D>::first_non_finite_particle() const {
  const auto& P = sc_.particles;
  for (std::size_t p = 0; p < P.size(); ++p) {
    const Sym3& st = P.stress[p];
    const char* what = !std::isfinite(P.mass[p])                                       ? "mass"
                       : !std::isfinite(P.volume[p])                                   ? "volume"
                       : !P.x[p].allFinite()                                           ? "position"
                       : !P.v[p].allFinite()                                           ? "velocity"
                       : !std::isfinite(st.xx + st.yy + st.zz + st.xy + st.yz + st.zx) ? "stress"
                                                                                       : nullptr;
    if (what)
      return fmt::format("; particle {} (material '{}') has a non-finite {}", p, sc_.material_names[P.material[p]],
                         what);
  }
  return "";
}

template <int D>
std::vector<double> Runner<D>::row_values(const Measurement& m, int) {
  std::vector<double> v = {0,
                           m.t,
                           m.dt,
                           m.strain,
                           m.punch_velocity,
                           m.punch_force,
                           m.punch_stress,
                           m.wall_left,
                           m.wall_right,
                           m.wall_bottom,
                           m.wall_stress,
                           m.mean_stress.xx,
                           m.mean_stress.yy,
                           m.mean_stress.zz,
                           m.mean_stress.xy,
                           m.kinetic,
                           m.internal,
                           m.dissipated,
                           m.punch_work,
                           m.ke_ie,
                           m.mass};
  for (double x : m.momentum) v.push_back(x);
  for (double x : m.com_velocity) v.push_back(x);
  for (auto& f : m.body_force)
    for (double x : f) v.push_back(x);
  for (auto& f : m.pair_force)
    for (double x : f) v.push_back(x);
  for (double x : m.field_overlap) v.push_back(x);
  for (double x : m.layer_energy) v.push_back(x);
  return v;
}

template <int D>
void Runner<D>::write_snapshot() {
  if (opt_.out_dir.empty()) return;
  const auto& P = sc_.particles;
  SnapshotData s;
  s.time = solver_.time();
  s.dim = D;
  s.count = P.size();
  s.position.assign(3 * s.count, 0.0);
  s.velocity.assign(3 * s.count, 0.0);
  s.stress.resize(6 * s.count);
  s.pressure.resize(s.count);
  s.von_mises.resize(s.count);
  s.plastic_strain.resize(s.count);
  s.volume = P.volume;
  s.material.assign(P.material.begin(), P.material.end());
  s.field.assign(P.field.begin(), P.field.end());
  for (std::size_t b = 0; b < sc_.bodies.size(); ++b) {
    const auto& body = sc_.bodies[b];
    s.rigid_body_names.push_back(body.name);
    for (const auto& xr : body.x) {
      for (int d = 0; d < 3; ++d) s.rigid_position.push_back(d < D ? xr[d] : 0.0);
      s.rigid_body.push_back(static_cast<int>(b));
    }
  }
  s.rigid_count = s.rigid_body.size();
  for (std::size_t p = 0; p < s.count; ++p) {
    for (int d = 0; d < D; ++d) {
      s.position[3 * p + d] = P.x[p][d];
      s.velocity[3 * p + d] = P.v[p][d];
    }
    const Sym3& st = P.stress[p];
    // XDMF's Tensor6 order, which ParaView expands into the 3 x 3 tensor (xx, yy, zz, xy, ... made
    // ParaView show sigma_yy as its XY component and every invariant wrong)
    const double c[6] = {st.xx, st.xy, st.zx, st.yy, st.yz, st.zz};
    for (int k = 0; k < 6; ++k) s.stress[6 * p + k] = c[k];
    s.pressure[p] = -st.mean();
    s.von_mises[p] = st.von_mises();
    const auto m = static_cast<std::size_t>(P.material[p]);
    const int hs = sc_.materials[m]->history_size();
    s.plastic_strain[p] =
        hs > 0 ? sc_.materials[m]->plastic_strain(sc_.material_state[m].history.data() + P.slot[p] * hs) : 0.0;
  }
  snapshots_.write(s);
}

template <int D>
std::string Runner<D>::this_and_earlier_versions() const {
  const std::string now = fmt::format("{} ({})", PBXMPM_VERSION, PBXMPM_GIT);
  return code_versions_.empty() ? now : code_versions_ + "; " + now;
}

template <int D>
void Runner<D>::write_run_json(const std::string& status, const std::string& message) const {
  if (opt_.out_dir.empty()) return;
  const auto& P = sc_.particles;
  const double wall = wall_before_ + now_s() - wall_start_;
  const double steps = static_cast<double>(solver_.step_count() - steps_unclocked_);
  double mass = 0, vol = 0;
  for (std::size_t p = 0; p < P.size(); ++p) {
    mass += P.mass[p];
    vol += P.volume0[p];
  }
  Json specimen;  // null without a die
  if (sc_.die) {
    const double box = sc_.die->width * sc_.die->height;
    specimen = {{"density_kg_m3", mass / box},
                {"porosity", 1.0 - vol / box},
                {"tmd_kg_m3", mass / vol},
                {"width_m", sc_.die->width},
                {"height_m", sc_.die->height}};
    if (sc_.packing_stats) {  // the packed geometry's porosity, which the particles rasterise
      specimen["packing_porosity"] = sc_.packing_stats->porosity;
      specimen["colours"] = sc_.packing_stats->colours;
    }
  }
  Json mats = Json::array();
  for (std::size_t m = 0; m < sc_.materials.size(); ++m)
    mats.push_back({{"name", sc_.material_names[m]},
                    {"model", sc_.materials[m]->model()},
                    {"density_kg_m3", sc_.materials[m]->density()},
                    {"particles", sc_.material_state[m].index.size()}});
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
  j["particles"] = P.size();
  j["rigid_particles"] = rigid;
  j["grid_nodes"] = sc_.grid.nodes();
  j["fields"] = sc_.grid.fields;
  j["steps"] = solver_.step_count();
  j["time_s"] = solver_.time();
  j["wall_time_s"] = rounded(wall, 4);
  j["restarts"] = restarts_;
  j["particle_updates_per_s"] = wall > 0 ? rounded(static_cast<double>(P.size()) * steps / wall, 0) : 0.0;
  j["peak_memory_MB"] = rounded(peak_memory_mb(), 1);
  {
    // where this segment's wall time went: the step's stages (solver/stage_clock.hpp), and the
    // rest of the run (history rows, field overlap, snapshots, checkpoints, progress)
    const StageClock& c = solver_.stage_clock();
    Json stages;
    for (std::size_t s = 0; s < kStageNames.size(); ++s)
      stages[kStageNames[s]] = rounded(c.seconds(static_cast<Stage>(s)), 4);
    stages["outside_steps"] = rounded(std::max(0.0, now_s() - wall_start_ - c.total()), 4);
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

namespace {
// Fingerprint of what the rebuilt scene gives and a checkpoint does not store: each particle's
// material, field and mass (FNV-1a over their bits, 52 bits so a double holds it exactly). The
// particle count alone let a re-packed specimen of the same count resume with the wrong grains.
template <int D>
double layout_fingerprint(const Particles<D>& P) {
  std::uint64_t h = 1469598103934665603ull;
  auto mix = [&](std::uint64_t v) {
    for (int b = 0; b < 8; ++b) {
      h ^= (v >> (8 * b)) & 0xffu;
      h *= 1099511628211ull;
    }
  };
  for (std::size_t p = 0; p < P.size(); ++p) {
    mix(static_cast<std::uint64_t>(P.material[p]));
    mix(static_cast<std::uint64_t>(P.field[p]));
    std::uint64_t m;
    std::memcpy(&m, &P.mass[p], sizeof m);
    mix(m);
  }
  return static_cast<double>(h >> 12);
}
}  // namespace

template <int D>
void Runner<D>::write_checkpoint(const std::string& file) const {
  const auto& P = sc_.particles;
  CheckpointData c;
  c.deck_text = opt_.deck_text;
  c.deck_name = opt_.deck_name;
  c.code_versions = this_and_earlier_versions();
  c.run_id = run_id_;
  const auto st = solver_.state();
  c.scalars = {{"t", st.t},
               {"dt", st.dt},
               {"cmax", st.cmax},
               {"vmax", st.vmax},
               {"internal", st.internal},
               {"dissipated", st.dissipated},
               {"steps", static_cast<double>(st.steps)},
               {"t_last_row", t_last_row_},
               {"punch_work", punch_work_},
               {"next_row", static_cast<double>(next_row_)},
               {"next_snapshot", static_cast<double>(next_snapshot_)},
               {"rows_written", static_cast<double>(rows_written_)},
               {"particles", static_cast<double>(P.size())},
               {"layout", layout_fingerprint(P)},
               {"wall_s", wall_before_ + now_s() - wall_start_},
               {"restarts", static_cast<double>(restarts_)}};
  auto flat = [&](const std::string& name, auto const& vec, int comps, auto get) {
    std::vector<double> out;
    out.reserve(vec.size() * static_cast<std::size_t>(comps));
    for (const auto& e : vec) get(e, out);
    c.arrays[name] = std::move(out);
  };
  auto vec_get = [](const Vec<D>& e, std::vector<double>& o) {
    for (int d = 0; d < D; ++d) o.push_back(e[d]);
  };
  auto mat_get = [](const Mat<D>& e, std::vector<double>& o) {
    for (int k = 0; k < D * D; ++k) o.push_back(e.data()[k]);
  };
  flat("x", P.x, D, vec_get);
  flat("v", P.v, D, vec_get);
  flat("F", P.F, D * D, mat_get);
  flat("L", P.L, D * D, mat_get);
  flat("stress", P.stress, 6, [](const Sym3& e, std::vector<double>& o) {
    o.insert(o.end(), {e.xx, e.yy, e.zz, e.xy, e.yz, e.zx});
  });
  c.arrays["volume"] = P.volume;
  for (std::size_t m = 0; m < sc_.material_state.size(); ++m)
    c.arrays[fmt::format("history_{}", m)] = sc_.material_state[m].history;
  std::vector<double> snaps;
  for (auto& [t, n] : snapshots_.written()) snaps.insert(snaps.end(), {t, static_cast<double>(n)});
  c.arrays["snapshots"] = snaps;
  if (sc_.settings.integrator == Integrator::usf) {
    // the velocities of the last contact pass that the next step's velocity gradient takes
    // (Solver::contact_velocities): node-field index and velocity, D + 1 numbers each
    std::vector<double> cv;
    for (const auto& [k, v] : solver_.contact_velocities()) {
      cv.push_back(static_cast<double>(k));
      for (int d = 0; d < D; ++d) cv.push_back(v[d]);
    }
    c.arrays["contact_velocities"] = cv;
  }
  pbx::write_checkpoint(file, c);
}

template <int D>
void Runner<D>::resume(const CheckpointData& c) {
  auto& P = sc_.particles;
  auto scalar = [&](const char* k) {
    auto it = c.scalars.find(k);
    if (it == c.scalars.end()) throw InputError(fmt::format("checkpoint lacks '{}'", k));
    return it->second;
  };
  auto array = [&](const std::string& k, std::size_t n) -> const std::vector<double>& {
    auto it = c.arrays.find(k);
    if (it == c.arrays.end() || it->second.size() != n)
      throw InputError(fmt::format("checkpoint array '{}' is missing or has the wrong size for this deck", k));
    return it->second;
  };
  // A checkpoint continues only its own run: resumed into a folder holding another run, it would
  // cut that run's history and append its own rows.
  if (!opt_.out_dir.empty()) {
    const std::string here = run_id_in(opt_.out_dir);
    if (!here.empty() && here != c.run_id)
      throw InputError(
          fmt::format("restart: '{}' holds another run (run_id {}) than the checkpoint's ({}); a checkpoint "
                      "continues only in its own run's folder",
                      opt_.out_dir, here, c.run_id.empty() ? "not recorded" : c.run_id));
  }
  run_id_ = c.run_id.empty() ? new_run_id() : c.run_id;
  const std::size_t n = P.size();
  if (static_cast<std::size_t>(scalar("particles")) != n)
    throw InputError("checkpoint particle count differs from the deck's: the deck or packing changed");
  // absent from checkpoints written before 2026-12-02: not checked for them
  if (auto it = c.scalars.find("layout"); it != c.scalars.end() && it->second != layout_fingerprint(P))
    throw InputError(
        "checkpoint particles (materials, fields or masses) differ from the deck's at the same count: "
        "the packing, or the code that builds the specimen, changed; rerun from the start");
  const auto& x = array("x", n * D);
  const auto& v = array("v", n * D);
  const auto& F = array("F", n * D * D);
  const auto& L = array("L", n * D * D);
  const auto& s = array("stress", n * 6);
  P.volume = array("volume", n);
  for (std::size_t p = 0; p < n; ++p) {
    for (int d = 0; d < D; ++d) {
      P.x[p][d] = x[p * D + d];
      P.v[p][d] = v[p * D + d];
    }
    for (int k = 0; k < D * D; ++k) {
      P.F[p].data()[k] = F[p * D * D + k];
      P.L[p].data()[k] = L[p * D * D + k];
    }
    P.stress[p] = {s[6 * p], s[6 * p + 1], s[6 * p + 2], s[6 * p + 3], s[6 * p + 4], s[6 * p + 5]};
  }
  for (std::size_t m = 0; m < sc_.material_state.size(); ++m)
    sc_.material_state[m].history = array(fmt::format("history_{}", m), sc_.material_state[m].history.size());
  typename Solver<D>::State st{scalar("t"),
                               scalar("dt"),
                               scalar("cmax"),
                               scalar("vmax"),
                               scalar("internal"),
                               scalar("dissipated"),
                               static_cast<long>(scalar("steps"))};
  solver_.restore(st);
  if (sc_.settings.integrator == Integrator::usf) {
    // absent from checkpoints written before 2026-12-05: the first step takes L from the
    // interpolated velocities alone, as USF did then
    typename Solver<D>::ContactVelocities cv;
    if (c.arrays.count("contact_velocities")) {
      const auto& a = c.arrays.at("contact_velocities");
      const double nd = static_cast<double>(sc_.grid.nodes()) * sc_.deformable_fields;
      if (a.size() % (D + 1) != 0)
        throw InputError("checkpoint array 'contact_velocities' has the wrong size for this deck");
      for (std::size_t i = 0; i < a.size(); i += D + 1) {
        if (!(a[i] >= 0 && a[i] < nd))
          throw InputError("checkpoint array 'contact_velocities' names a node outside this deck's grid");
        Vec<D> v;
        for (int d = 0; d < D; ++d) v[d] = a[i + 1 + static_cast<std::size_t>(d)];
        cv.emplace_back(static_cast<long>(a[i]), v);
      }
    }
    solver_.restore_contact_velocities(std::move(cv));
  }
  t_last_row_ = scalar("t_last_row");
  punch_work_ = scalar("punch_work");
  next_row_ = static_cast<int>(scalar("next_row"));
  next_snapshot_ = static_cast<int>(scalar("next_snapshot"));
  rows_written_ = static_cast<int>(scalar("rows_written"));
  // absent from checkpoints written before 2026-12-02: their earlier wall time is unknown, so
  // the rates count only the steps made since
  wall_before_ = c.scalars.count("wall_s") ? c.scalars.at("wall_s") : 0.0;
  steps_unclocked_ = c.scalars.count("wall_s") ? 0 : st.steps;
  code_versions_ = c.code_versions.empty() ? "unknown" : c.code_versions;
  restarts_ = (c.scalars.count("restarts") ? static_cast<int>(c.scalars.at("restarts")) : 0) + 1;
  const auto& snaps = c.arrays.count("snapshots") ? c.arrays.at("snapshots") : std::vector<double>{};
  std::vector<std::pair<double, std::size_t>> w;
  for (std::size_t i = 0; i + 1 < snaps.size(); i += 2)
    w.emplace_back(snaps[i], static_cast<std::size_t>(snaps[i + 1]));
  std::size_t rigid = 0;
  for (const auto& b : sc_.bodies) rigid += b.x.size();
  snapshots_.restore(w, rigid);
  // keep the header and the rows the checkpoint had written, then append
  if (!opt_.out_dir.empty()) {
    const auto file = (std::filesystem::path(opt_.out_dir) / "history.csv").string();
    std::ifstream in(file);
    if (!in) throw InputError(fmt::format("restart: '{}' is missing", file));
    std::string line, kept;
    int lines = 0;
    for (; lines <= rows_written_ && std::getline(in, line); ++lines) kept += line + "\n";
    in.close();
    if (lines != rows_written_ + 1)
      throw InputError(fmt::format("restart: '{}' has {} rows, the checkpoint was written after {}", file,
                                   std::max(0, lines - 1), rows_written_));
    // The appended rows follow this code's columns: a history written by a version with other
    // columns (e.g. before field_overlap_m2_per_m) would get rows that do not match its header.
    if (kept.substr(0, kept.find('\n')) != CsvWriter::header(columns_))
      throw InputError(
          fmt::format("restart: the columns of '{}' differ from the ones this version writes "
                      "(the checkpoint comes from another code version); rerun from the start",
                      file));
    // a run killed here keeps the history it had (which the checkpoint's restart cuts again)
    write_text_atomically(file, kept);
    history_ = CsvWriter(file, columns_, true);
  }
  resumed_ = true;
}

template <int D>
void Runner<D>::run(const std::function<void(const Measurement&)>& on_row) {
  wall_start_ = now_s();
  solver_.stage_clock().clear();
  const double t_end = sc_.control.end_time;
  steps_at_start_ = solver_.step_count();
  frac_at_start_ = std::min(1.0, solver_.time() / t_end);
  const int rows = sc_.control.history_points;
  Measurement last;  // the final progress line shows the last measured state, not an empty one
  auto emit_row = [&] {
    Measurement m = measure();
    last = m;
    auto v = row_values(m, static_cast<int>(sc_.bodies.size()));
    v[0] = static_cast<double>(solver_.step_count());
    // The particle checks see velocities and stresses; a NaN that reaches only the sums (mass,
    // energies, reactions) must stop the run too. The row is not written: history.csv holds only
    // finite rows, so a failed run can still be analysed up to its failure.
    for (std::size_t c = 0; c < v.size(); ++c)
      if (!std::isfinite(v[c]))
        throw InstabilityError(fmt::format("step {} (t = {:.6g} s): history column '{}' is {}{}", solver_.step_count(),
                                           solver_.time(), columns_[c], v[c], first_non_finite_particle()));
    if (history_.open()) history_.row(v);
    ++rows_written_;
    if (on_row) on_row(m);
    report_progress(m, false);
    return m;
  };
  write_run_json("running", "");
  StopSignals signals(opt_.catch_signals);
  last_checkpoint_wall_ = now_s();
  const auto checkpoint_file = (std::filesystem::path(opt_.out_dir) / "checkpoint.h5").string();
  bool told = false;
  try {
    if (!resumed_) {
      emit_row();
      next_row_ = 1;
      if (sc_.control.snapshots > 0) write_snapshot();
      next_snapshot_ = 1;
    }
    while (solver_.time() < t_end * (1 - 1e-12)) {
      // the last step is shortened to land on the end time (a run of fewer steps than history
      // rows overshot its end strain by up to a whole step)
      solver_.step(t_end - solver_.time());
      const double t = solver_.time();
      bool row = false;
      if (t >= t_end * next_row_ / (rows - 1) || t >= t_end * (1 - 1e-12)) {
        emit_row();
        row = true;
        while (t_end * next_row_ / (rows - 1) <= t) ++next_row_;
      }
      if (sc_.control.snapshots > 0 && t >= t_end * next_snapshot_ / sc_.control.snapshots) {
        write_snapshot();
        while (t_end * next_snapshot_ / sc_.control.snapshots <= t) ++next_snapshot_;
      }
      const bool stop = g_stop_signal.load() != 0;
      if (stop && !told) {
        told = true;
        std::fprintf(stderr,
                     "%spbxmpm: %s received: finishing the run up to its next history row, then saving a "
                     "checkpoint (a second one stops at once)\n",
                     tty_ && opt_.progress ? "\n" : "", g_stop_signal.load() == SIGINT ? "SIGINT" : "SIGTERM");
      }
      // Checkpoints are taken right after a row, where the force accumulators have just been
      // reset: a restart from one continues bit for bit.
      if (!row || opt_.out_dir.empty()) {
        if (stop && opt_.out_dir.empty())
          throw Interrupted("interrupted by a signal (no output folder: nothing saved)");
        continue;
      }
      const bool more = solver_.time() < t_end * (1 - 1e-12);
      const bool periodic = (opt_.checkpoint_every > 0 && rows_written_ % opt_.checkpoint_every == 0) ||
                            (opt_.checkpoint_wall_s > 0 && now_s() - last_checkpoint_wall_ >= opt_.checkpoint_wall_s);
      if (more && (periodic || stop)) {
        write_checkpoint(checkpoint_file);
        last_checkpoint_wall_ = now_s();
      }
      if (stop && more) stop_interrupted();
    }
  } catch (const Interrupted&) {
    throw;
  } catch (const InstabilityError& e) {
    if (opt_.progress && tty_) std::fprintf(stderr, "\n");
    try {
      write_snapshot();
    } catch (...) {
    }
    write_run_json("failed", e.what());
    throw;
  } catch (const std::exception& e) {  // e.g. a checkpoint or snapshot that could not be written
    if (opt_.progress && tty_) std::fprintf(stderr, "\n");
    try {  // a full disk may refuse run.json too: the first error is the one to report
      write_run_json("failed", e.what());
    } catch (const std::exception& e2) {
      std::fprintf(stderr, "pbxmpm: run.json could not be marked failed either: %s\n", e2.what());
    }
    throw;
  }
  last.t = solver_.time();
  report_progress(last, true);
  write_run_json("finished", "");
}

template <int D>
void Runner<D>::stop_interrupted() {
  const auto ckpt = std::filesystem::path(opt_.out_dir) / "checkpoint.h5";
  const std::string msg =
      fmt::format("interrupted at step {} (t = {:.6g} s, {} history rows); continue with: pbxmpm run --restart {}",
                  solver_.step_count(), solver_.time(), rows_written_, ckpt.string());
  write_run_json("interrupted", msg);
  throw Interrupted(msg);
}

template class Runner<2>;
template class Runner<3>;

}  // namespace pbx
