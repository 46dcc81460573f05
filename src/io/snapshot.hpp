#pragma once
// Particle snapshots: one HDF5 file per snapshot (snapshots/snap_NNNN.h5) plus an XDMF sidecar
// (snapshots/snapshots.xmf, a temporal collection) that ParaView opens directly. Rewritten after
// every snapshot so an interrupted run stays readable. Units: SI (m, m/s, Pa, m^2 per m depth).
#include <string>
#include <vector>

namespace pbx {

struct SnapshotData {
  double time = 0;                      // s
  int dim = 2;
  std::size_t count = 0;
  std::vector<double> position;         // count x 3 (z = 0 in 2D), m
  std::vector<double> velocity;         // count x 3, m/s
  std::vector<double> stress;           // count x 6 (xx, yy, zz, xy, yz, zx), Pa
  std::vector<double> pressure;         // -tr(sigma)/3, Pa
  std::vector<double> von_mises;        // Pa
  std::vector<double> plastic_strain;   // equivalent plastic strain, 1
  std::vector<double> volume;           // m^2 (per m of depth) in 2D
  std::vector<int> material, field;
};

class SnapshotWriter {
 public:
  SnapshotWriter() = default;
  explicit SnapshotWriter(std::string dir) : dir_(std::move(dir)) {}
  void write(const SnapshotData& s);
  const std::string& dir() const { return dir_; }

 private:
  void write_xdmf() const;
  std::string dir_;
  struct Entry {
    std::string file;
    double time;
    std::size_t count;
  };
  std::vector<Entry> entries_;
};

}  // namespace pbx
