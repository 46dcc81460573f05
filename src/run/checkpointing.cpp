// Checkpoints: what a run saves to continue bit for bit, and the restart that verifies and restores it.
#include "run/runner.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>

#include <fmt/format.h>

#include "core/error.hpp"
#include "io/atomic_write.hpp"

#include "pbxmpm_git.hpp"  // PBXMPM_GIT, generated at build time
#include "run/run_id.hpp"
#include "run/wall_clock.hpp"

namespace pbx {

namespace {
// Fingerprint of what the rebuilt scene gives and a checkpoint does not store: each particle's
// material, field and mass (FNV-1a over their bits, 52 bits so a double holds it exactly). The
// particle count alone let a re-packed specimen of the same count resume with the wrong grains.
// `layout`: material, field and mass of each particle, three doubles each (the integers exact).
double layout_fingerprint(const std::vector<double>& layout) {
  std::uint64_t h = 1469598103934665603ull;
  auto mix = [&](std::uint64_t v) {
    for (int b = 0; b < 8; ++b) {
      h ^= (v >> (8 * b)) & 0xffu;
      h *= 1099511628211ull;
    }
  };
  for (std::size_t k = 0; k + 2 < layout.size(); k += 3) {
    mix(static_cast<std::uint64_t>(layout[k]));
    mix(static_cast<std::uint64_t>(layout[k + 1]));
    std::uint64_t m;
    std::memcpy(&m, &layout[k + 2], sizeof m);
    mix(m);
  }
  return static_cast<double>(h >> 12);
}
}  // namespace

// Every rank's values of a per-particle array in rank order: the whole specimen's in storage order
// (a run over ranks; one process: its own).
template <int D>
std::vector<double> Runner<D>::whole_array(const std::vector<double>& mine) const {
  return opt_.exchange ? opt_.exchange->in_rank_order(mine) : mine;
}

template <int D>
double Runner<D>::whole_layout_fingerprint() const {
  const auto& P = sc_.particles;
  std::vector<double> layout;
  layout.reserve(3 * P.size());
  for (std::size_t p = 0; p < P.size(); ++p)
    layout.insert(layout.end(), {static_cast<double>(P.material[p]), static_cast<double>(P.field[p]), P.mass[p]});
  return layout_fingerprint(whole_array(layout));
}

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
               {"friction_work", st.friction},
               {"steps", static_cast<double>(st.steps)},
               {"t_last_row", t_last_row_},
               {"punch_work", punch_work_},
               {"next_row", static_cast<double>(next_row_)},
               {"next_snapshot", static_cast<double>(next_snapshot_)},
               {"rows_written", static_cast<double>(rows_written_)},
               {"particles", static_cast<double>(whole_.particles)},
               {"layout", whole_layout_fingerprint()},
               {"wall_s", wall_before_ + now_s() - wall_start_},
               {"restarts", static_cast<double>(restarts_)}};
  // A run over ranks writes the one-process file: every array gathered in rank order, which is the
  // whole specimen's storage order (and each material's batch order), so a checkpoint written on
  // N ranks restarts on any number.
  auto flat = [&](const std::string& name, auto const& vec, int comps, auto get) {
    std::vector<double> out;
    out.reserve(vec.size() * static_cast<std::size_t>(comps));
    for (const auto& e : vec) get(e, out);
    c.arrays[name] = whole_array(out);
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
  c.arrays["volume"] = whole_array(P.volume);
  for (std::size_t m = 0; m < sc_.material_state.size(); ++m)
    c.arrays[fmt::format("history_{}", m)] = whole_array(sc_.material_state[m].history);
  std::vector<double> snaps;
  for (auto& [t, n] : snapshots_.written()) snaps.insert(snaps.end(), {t, static_cast<double>(n)});
  c.arrays["snapshots"] = snaps;
  c.arrays["dissipated_by_material"] = st.dissipated_by_material;
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
  if (writer_) pbx::write_checkpoint(file, c);
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
  if (writer_) {
    const std::string here = run_id_in(opt_.out_dir);
    if (!here.empty() && here != c.run_id)
      throw InputError(
          fmt::format("restart: '{}' holds another run (run_id {}) than the checkpoint's ({}); a checkpoint "
                      "continues only in its own run's folder",
                      opt_.out_dir, here, c.run_id.empty() ? "not recorded" : c.run_id));
  }
  run_id_ = c.run_id.empty() ? new_run_id() : c.run_id;
  const std::size_t n = P.size(), whole = whole_.particles;
  if (static_cast<std::size_t>(scalar("particles")) != whole)
    throw InputError("checkpoint particle count differs from the deck's: the deck or packing changed");
  // absent from checkpoints written before 2026-12-02: not checked for them
  if (auto it = c.scalars.find("layout"); it != c.scalars.end() && it->second != whole_layout_fingerprint())
    throw InputError(
        "checkpoint particles (materials, fields or masses) differ from the deck's at the same count: "
        "the packing, or the code that builds the specimen, changed; rerun from the start");
  // This process's part of the whole specimen's arrays: from its first particle, and in each
  // material's batch from its first row (a run over ranks: the counts of the ranks below).
  const std::size_t nm = sc_.material_state.size();
  std::size_t first = 0;
  std::vector<std::size_t> first_row(nm, 0);
  if (opt_.exchange) {
    std::vector<double> counts = {static_cast<double>(n)};
    for (std::size_t m = 0; m < nm; ++m) counts.push_back(static_cast<double>(sc_.material_state[m].index.size()));
    const std::vector<double> all = opt_.exchange->in_rank_order(counts);
    for (int r = 0; r < opt_.rank; ++r) {
      first += static_cast<std::size_t>(all[static_cast<std::size_t>(r) * (nm + 1)]);
      for (std::size_t m = 0; m < nm; ++m)
        first_row[m] += static_cast<std::size_t>(all[static_cast<std::size_t>(r) * (nm + 1) + 1 + m]);
    }
  }
  const auto& x = array("x", whole * D);
  const auto& v = array("v", whole * D);
  const auto& F = array("F", whole * D * D);
  const auto& L = array("L", whole * D * D);
  const auto& s = array("stress", whole * 6);
  const auto& vol = array("volume", whole);
  P.volume.assign(vol.begin() + static_cast<long>(first), vol.begin() + static_cast<long>(first + n));
  for (std::size_t p = 0; p < n; ++p) {
    const std::size_t q = first + p;
    for (int d = 0; d < D; ++d) {
      P.x[p][d] = x[q * D + d];
      P.v[p][d] = v[q * D + d];
    }
    for (int k = 0; k < D * D; ++k) {
      P.F[p].data()[k] = F[q * D * D + k];
      P.L[p].data()[k] = L[q * D * D + k];
    }
    P.stress[p] = {s[6 * q], s[6 * q + 1], s[6 * q + 2], s[6 * q + 3], s[6 * q + 4], s[6 * q + 5]};
  }
  for (std::size_t m = 0; m < nm; ++m) {
    auto& h = sc_.material_state[m].history;
    const std::size_t hs = static_cast<std::size_t>(sc_.materials[m]->history_size());
    const auto& all = array(fmt::format("history_{}", m), whole_.by_material[m] * hs);
    h.assign(all.begin() + static_cast<long>(first_row[m] * hs),
             all.begin() + static_cast<long>((first_row[m] + sc_.material_state[m].index.size()) * hs));
  }
  typename Solver<D>::State st{scalar("t"),
                               scalar("dt"),
                               scalar("cmax"),
                               scalar("vmax"),
                               scalar("internal"),
                               scalar("dissipated"),
                               static_cast<long>(scalar("steps")),
                               {},
                               0.0};
  // the dissipation's parts (absent from checkpoints written before 2026-12-06: the history's
  // split columns then carry all earlier dissipation as friction)
  if (c.arrays.count("dissipated_by_material")) {
    st.dissipated_by_material = array("dissipated_by_material", sc_.materials.size());
    st.friction = scalar("friction_work");
  }
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
  if (writer_) {
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

template std::vector<double> Runner<2>::whole_array(const std::vector<double>&) const;
template double Runner<2>::whole_layout_fingerprint() const;
template std::vector<double> Runner<3>::whole_array(const std::vector<double>&) const;
template double Runner<3>::whole_layout_fingerprint() const;
template void Runner<2>::write_checkpoint(const std::string&) const;
template void Runner<2>::resume(const CheckpointData&);
template void Runner<3>::write_checkpoint(const std::string&) const;
template void Runner<3>::resume(const CheckpointData&);

}  // namespace pbx
