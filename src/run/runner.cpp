#include "run/runner.hpp"

#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <atomic>
#include <csignal>
#include <filesystem>

#include <fmt/format.h>

#include "io/atomic_write.hpp"
#include "io/json.hpp"
#include <omp.h>
#include <unistd.h>

#include "core/error.hpp"
#include "pbxmpm_git.hpp"  // PBXMPM_GIT, generated at build time
#include "run/run_id.hpp"
#include "run/wall_clock.hpp"

namespace pbx {

namespace {

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

}  // namespace

RunOptions run_options_for(const Deck& deck, const std::string& deck_name, const std::string& out_dir) {
  RunOptions opt;
  opt.out_dir = out_dir;
  opt.deck = json_parse(deck.to_json(), "the deck as JSON");
  opt.deck_text = deck.text();
  opt.deck_name = deck_name;
  return opt;
}

template <int D>
Runner<D>::Runner(Scene<D>& scene, RunOptions opt, bool restart) : sc_(scene), opt_(std::move(opt)), solver_(scene) {
  saves_ = !opt_.out_dir.empty();
  writer_ = saves_ && opt_.rank == 0;
  if (opt_.exchange) {
    solver_.set_scatter_exchange(opt_.exchange, opt_.mass_threshold);
  }
  {
    // strip by strip, so that one process and any number of ranks give the same bits
    const auto& P = sc_.particles;
    const StripBins& strips = solver_.strips();
    const std::size_t nm = sc_.materials.size();
    struct Count {
      std::vector<double> v;  // particles, mass, initial volume, then particles per material
      Count& operator+=(const Count& o) {
        for (std::size_t k = 0; k < v.size(); ++k) v[k] += o.v[k];
        return *this;
      }
      void each_double(const std::function<void(double&)>& f) {
        for (double& x : v) f(x);
      }
    };
    const Count c = strips.fold(Count{std::vector<double>(3 + nm, 0.0)}, [&](long s, Count& r) {
      for (long p = strips.begin[static_cast<std::size_t>(s)]; p < strips.begin[static_cast<std::size_t>(s + 1)]; ++p) {
        r.v[0] += 1;
        r.v[1] += P.mass[p];
        r.v[2] += P.volume0[p];
        r.v[3 + static_cast<std::size_t>(P.material[p])] += 1;
      }
    });
    whole_.particles = static_cast<std::size_t>(c.v[0]);
    whole_.mass = c.v[1];
    whole_.volume0 = c.v[2];
    for (std::size_t m = 0; m < nm; ++m) whole_.by_material.push_back(static_cast<std::size_t>(c.v[3 + m]));
  }
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
    if (sc_.deformable_fields > 1 && whole_.particles > 0) {
      // the pixel from the whole specimen's smallest particle (a rank holds a part of it)
      const double pixel = FieldOverlap::default_pixel(sc_.particles);
      overlap_.emplace(sc_.grid,
                       opt_.exchange ? -opt_.exchange->max(-(sc_.particles.size() ? pixel : HUGE_VAL)) : pixel);
      columns_.push_back("field_overlap_m2_per_m");
    }
  }
  if (sc_.contact.has_layers()) columns_.push_back("layer_energy_J" + per);
  // the dissipation's parts (they sum to dissipated_J): where a run's energy goes; the contact's
  // work is its friction plus the plastic work of flowing binder films
  for (const auto& name : sc_.material_names) columns_.push_back(fmt::format("dissipated_{}_J{}", name, per));
  columns_.push_back("contact_work_J" + per);
  columns_.push_back("max_particle_speed_m_s");
  if (writer_) {
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
void Runner<D>::write_snapshot() {
  if (!saves_) return;
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
  if (opt_.exchange) {
    // every rank's particles, in rank order: the one-process storage order (18 doubles each; the
    // integers are exact as doubles)
    constexpr std::size_t w = 18;
    std::vector<double> mine;
    mine.reserve(w * s.count);
    for (std::size_t p = 0; p < s.count; ++p) {
      for (int k = 0; k < 3; ++k) mine.push_back(s.position[3 * p + k]);
      for (int k = 0; k < 3; ++k) mine.push_back(s.velocity[3 * p + k]);
      for (int k = 0; k < 6; ++k) mine.push_back(s.stress[6 * p + k]);
      for (double x : {s.pressure[p], s.von_mises[p], s.plastic_strain[p], s.volume[p]}) mine.push_back(x);
      mine.push_back(static_cast<double>(s.material[p]));
      mine.push_back(static_cast<double>(s.field[p]));
    }
    const std::vector<double> all = opt_.exchange->in_rank_order(mine);
    if (!writer_) return;
    const std::size_t n = all.size() / w;
    SnapshotData a;
    a.time = s.time;
    a.dim = s.dim;
    a.count = n;
    for (std::size_t p = 0; p < n; ++p) {
      const double* r = all.data() + w * p;
      a.position.insert(a.position.end(), r, r + 3);
      a.velocity.insert(a.velocity.end(), r + 3, r + 6);
      a.stress.insert(a.stress.end(), r + 6, r + 12);
      a.pressure.push_back(r[12]);
      a.von_mises.push_back(r[13]);
      a.plastic_strain.push_back(r[14]);
      a.volume.push_back(r[15]);
      a.material.push_back(static_cast<int>(r[16]));
      a.field.push_back(static_cast<int>(r[17]));
    }
    a.rigid_count = s.rigid_count;
    a.rigid_position = std::move(s.rigid_position);
    a.rigid_body = std::move(s.rigid_body);
    a.rigid_body_names = std::move(s.rigid_body_names);
    s = std::move(a);
  }
  if (writer_) snapshots_.write(s);
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
      bool stop = g_stop_signal.load() != 0;
      // a decomposed run's ranks stop together, at a history row (a signal reaches them at different steps)
      if (opt_.exchange) stop = row && opt_.exchange->max(stop ? 1.0 : 0.0) > 0.0;
      if (stop && !told && opt_.rank == 0) {
        told = true;
        std::fprintf(stderr,
                     "%spbxmpm: %s received: finishing the run up to its next history row, then saving a "
                     "checkpoint (a second one stops at once)\n",
                     tty_ && opt_.progress ? "\n" : "", g_stop_signal.load() == SIGINT ? "SIGINT" : "SIGTERM");
      }
      // Checkpoints are taken right after a row, where the force accumulators have just been
      // reset: a restart from one continues bit for bit.
      if (!row || !saves_) {
        if (stop && !saves_) throw Interrupted("interrupted by a signal (no output folder: nothing saved)");
        continue;
      }
      const bool more = solver_.time() < t_end * (1 - 1e-12);
      bool periodic = (opt_.checkpoint_every > 0 && rows_written_ % opt_.checkpoint_every == 0) ||
                      (opt_.checkpoint_wall_s > 0 && now_s() - last_checkpoint_wall_ >= opt_.checkpoint_wall_s);
      // the ranks' clocks differ: they write (a collective gather) when any of them is due
      if (opt_.exchange) periodic = opt_.exchange->max(periodic ? 1.0 : 0.0) > 0.0;
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
      fmt::format("interrupted at step {} (t = {:.6g} s, {} history rows); continue with: {}pbxmpm run --restart {}{}",
                  solver_.step_count(), solver_.time(), rows_written_, opt_.exchange ? "mpirun -n N " : "",
                  ckpt.string(), opt_.exchange ? " (on any number of ranks, or one process)" : "");
  write_run_json("interrupted", msg);
  throw Interrupted(msg);
}

template class Runner<2>;
template class Runner<3>;

}  // namespace pbx
