#pragma once
// Particle snapshots: one HDF5 file per snapshot (snapshots/snap_NNNN.h5) plus an XDMF sidecar
// (snapshots/snapshots.xmf, a temporal collection) that ParaView opens directly. Each time holds
// two grids: "particles" (the specimen) and "rigid_bodies" (the die walls, punch and [[rigid]]
// bodies as their particles), so a viewer shows the specimen inside the die. Rewritten after
// every snapshot so an interrupted run stays readable. Units: SI (m, m/s, Pa, m^2 per m depth).
#include <string>
#include <vector>

namespace pbx {

struct SnapshotData {
  double time = 0;  // s
  int dim = 2;
  std::size_t count = 0;
  std::vector<double> position;        // count x 3 (z = 0 in 2D), m
  std::vector<double> velocity;        // count x 3, m/s
  std::vector<double> stress;          // count x 6 (xx, xy, xz, yy, yz, zz: XDMF Tensor6 order), Pa
  std::vector<double> pressure;        // -tr(sigma)/3, Pa
  std::vector<double> von_mises;       // Pa
  std::vector<double> plastic_strain;  // equivalent plastic strain, 1
  std::vector<double> volume;          // m^2 (per m of depth) in 2D
  std::vector<int> material, field;
  // The rigid bodies (die walls, punch, [[rigid]]) as their particles, so a viewer shows the die:
  std::size_t rigid_count = 0;
  std::vector<double> rigid_position;  // rigid_count x 3, m
  std::vector<int> rigid_body;         // index into rigid_body_names
  std::vector<std::string> rigid_body_names;
};

class SnapshotWriter {
 public:
  SnapshotWriter() = default;
  explicit SnapshotWriter(std::string dir) : dir_(std::move(dir)) {}
  void write(const SnapshotData& s);
  const std::string& dir() const { return dir_; }
  // Snapshots already written (checkpoint restart): times and particle counts, in order.
  std::vector<std::pair<double, std::size_t>> written() const {
    std::vector<std::pair<double, std::size_t>> out;
    for (auto& e : entries_) out.emplace_back(e.time, e.count);
    return out;
  }
  // rigid_count: the bodies' particle count, which does not change during a run
  void restore(const std::vector<std::pair<double, std::size_t>>& w, std::size_t rigid_count) {
    entries_.clear();
    for (std::size_t i = 0; i < w.size(); ++i)
      entries_.push_back({snapshot_name(i), w[i].first, w[i].second, rigid_count});
  }
  static std::string snapshot_name(std::size_t i);

 private:
  void write_xdmf() const;
  std::string dir_;
  struct Entry {
    std::string file;
    double time;
    std::size_t count;
    std::size_t rigid_count = 0;
  };
  std::vector<Entry> entries_;
};

}  // namespace pbx
