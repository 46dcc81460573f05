#pragma once
// The homogenised stress-strain curve of one run, read from RUN/history.csv. Every stress here is
// COMPRESSION POSITIVE (the volume-averaged Cauchy stresses of history.csv are tension positive
// and are negated on reading), strain is the punch displacement over the initial height.
#include <string>
#include <utility>
#include <vector>

namespace pbx {

struct StressStrainCurve {
  std::vector<double> strain;
  std::vector<double> punch_stress;      // Pa, punch force / contact length
  std::vector<double> wall_stress;       // Pa, mean side-wall force / current height
  std::vector<double> vol_axial;         // Pa, -<sigma_yy>
  std::vector<double> vol_lateral;       // Pa, -<sigma_xx>
  std::vector<double> vol_out_of_plane;  // Pa, -<sigma_zz>
  std::vector<double> ke_ie;             // kinetic / internal energy of the specimen
  std::vector<double> time;              // s
  std::vector<double> field_overlap;     // m^2 per m, overlapping domains of different fields (empty: not in the file)
  // J per m (3-D: J): kinetic energy, stress work, punch work (empty when the file has no energy columns)
  std::vector<double> kinetic, internal, punch_work;
  // the parts of the dissipated energy (history columns dissipated_<material>_J_per_m and
  // contact_work_J_per_m, written since 2026-12-06; empty in older files), J per m, and the fastest
  // particle's speed, m/s (empty in older files)
  std::vector<std::pair<std::string, std::vector<double>>> dissipation_parts;
  std::vector<double> max_particle_speed, punch_velocity;
  std::vector<double> mass;  // kg per m (3-D: kg), the specimen's unscaled mass (empty without the column)
  std::size_t size() const { return strain.size(); }

  // Reads the columns above from a history.csv; other columns are ignored. Rows with a
  // non-finite strain are dropped. Throws InputError naming a missing column.
  static StressStrainCurve from_history(const std::string& path);
};

// KE/IE of the motion beyond the die's affine velocity field, per row: a specimen compressed
// quasi-statically by a punch at speed v moves with v(y) = v y/H, whose kinetic energy
// f m v^2 / 6 (uniform mass over the height, mass scaling f) is no dynamics but stays a large share
// of the stress work early in the test (0.135 at 0.12 % strain on the quick specimen, where the whole
// KE/IE is 0.12). Returns max(0, KE - f m v^2/6) / IE (the history's ke_ie where IE <= 0), or the
// history's ke_ie when the energy, mass or punch velocity columns are absent or f is not a positive
// number. Where the estimate exceeds KE (a mass not spread evenly over the height) the clamp can hide
// a ringing of up to that excess, about 0.015 of IE on the quick specimen at 0.12-0.17 % strain.
std::vector<double> ke_ie_beyond_affine(const StressStrainCurve& c, double mass_scaling);

// Index range [begin, end) of the points with lo <= strain <= hi (strain need not be monotonic
// at the very start; points are taken in file order).
std::vector<std::size_t> points_in(const std::vector<double>& strain, double lo, double hi);

// Agreement of two measures of one stress over the points with strain >= from:
// rms and max of (a - b), relative to max |a|.
struct CurveDiscrepancy {
  double rms_relative = 0;
  double max_relative = 0;
  int points = 0;
};
CurveDiscrepancy curve_discrepancy(const std::vector<double>& strain, const std::vector<double>& a,
                                   const std::vector<double>& b, double from);

}  // namespace pbx
