#pragma once
// Material point driver: one particle of a material, no grid, driven through a prescribed velocity
// gradient history. Used to calibrate parameters (`pbxmpm material`) and by the material tests.
#include <iosfwd>
#include <string>
#include <vector>

#include "materials/material.hpp"

namespace pbx {

// One material point: F, stress and history; volume0 = 1 m^3 so energies are per unit reference volume.
template <int D>
class MaterialPoint {
 public:
  explicit MaterialPoint(const Material<D>& m);
  // Advances by dt with a velocity gradient L constant over the step (F <- exp(L dt) F).
  MaterialStepResult step(const Mat<D>& L, double dt);
  const Sym3& stress() const { return stress_; }
  const Mat<D>& F() const { return F_; }
  double J() const { return F_.determinant(); }
  double time() const { return time_; }
  double plastic_strain() const { return material_->plastic_strain(history_.data()); }
  double dissipated() const { return dissipated_; }  // J per m^3 of reference volume, cumulative
  double stress_work() const { return work_; }       // J per m^3 of reference volume, cumulative
  const std::vector<double>& history() const { return history_; }
  std::vector<double>& history() { return history_; }

 private:
  const Material<D>* material_;
  Sym3 stress_;
  Mat<D> F_ = Mat<D>::Identity();
  std::vector<double> history_;
  double mass_, time_ = 0, dissipated_ = 0, work_ = 0;
};

enum class PointPath { uniaxial_strain, uniaxial_stress, simple_shear, step_shear, hydrostatic };

// Parses a path name; throws InputError listing the known names.
PointPath parse_point_path(const std::string& name);
std::string point_path_name(PointPath p);

struct PointLoad {
  PointPath path = PointPath::uniaxial_strain;
  double strain = 0;    // target strain, signed (tension positive); see point_strain_meaning()
  double rate = 0;      // strain rate magnitude, 1/s (> 0); unused by step_shear
  double duration = 0;  // s; 0 = |strain|/rate. For step_shear: the hold time after the jump
  int steps = 1000;     // number of steps (constant-rate paths) or output times (step_shear)
};

// What the `strain` column means for each path.
std::string point_strain_meaning(PointPath p);

struct PointSample {
  double time = 0, strain = 0, J = 1;
  Sym3 stress;
  double plastic_strain = 0, dissipated = 0;
};

// Drives a 3D material point through `load`; the first sample is the unloaded state at t = 0.
// Throws InputError for a bad load (zero strain, non-positive rate, too few steps).
std::vector<PointSample> drive_point(const Material<3>& m, const PointLoad& load);

// CSV with units in the column names.
void write_point_csv(std::ostream& out, const std::vector<PointSample>& samples);

}  // namespace pbx
