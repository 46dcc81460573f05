#include "analysis/stress_strain_curve.hpp"

#include <algorithm>
#include <cmath>

#include "analysis/csv_table.hpp"

namespace pbx {

StressStrainCurve StressStrainCurve::from_history(const std::string& path) {
  const CsvTable t = CsvTable::read(path);  // every cell used must be a number: no row is skipped
  const auto& eps = t.numbers("strain");
  const auto& punch = t.numbers("punch_stress_Pa");
  const auto& wall = t.numbers("wall_stress_Pa");
  const auto& sxx = t.numbers("sxx_Pa");
  const auto& syy = t.numbers("syy_Pa");
  const auto& szz = t.numbers("szz_Pa");
  const auto& keie = t.numbers("ke_ie");
  const auto& time = t.numbers("t_s");
  const std::vector<double>* overlap = t.has("field_overlap_m2_per_m") ? &t.numbers("field_overlap_m2_per_m") : nullptr;
  // 2-D energies and masses are per metre of depth (kinetic_J_per_m, ...), 3-D ones totals (kinetic_J, ...)
  const std::string per = t.has("kinetic_J_per_m") || !t.has("kinetic_J") ? "_per_m" : "";
  const bool energy = t.has("kinetic_J" + per) && t.has("internal_J" + per) && t.has("punch_work_J" + per);
  StressStrainCurve c;
  if (energy) {
    c.kinetic = t.numbers("kinetic_J" + per);
    c.internal = t.numbers("internal_J" + per);
    c.punch_work = t.numbers("punch_work_J" + per);
    const std::string head = "dissipated_", tail = "_J" + per;
    for (const std::string& name : t.names())
      if (name.size() > head.size() + tail.size() && name.rfind(head, 0) == 0 &&
          name.compare(name.size() - tail.size(), tail.size(), tail) == 0)
        c.dissipation_parts.emplace_back(name.substr(head.size(), name.size() - head.size() - tail.size()),
                                         t.numbers(name));
    if (t.has("contact_work_J" + per)) c.dissipation_parts.emplace_back("contact", t.numbers("contact_work_J" + per));
  }
  if (t.has("max_particle_speed_m_s")) c.max_particle_speed = t.numbers("max_particle_speed_m_s");
  if (t.has("punch_velocity_m_s")) c.punch_velocity = t.numbers("punch_velocity_m_s");
  if (t.has("mass_kg" + per)) c.mass = t.numbers("mass_kg" + per);
  for (std::size_t i = 0; i < t.rows(); ++i) {
    c.strain.push_back(eps[i]);
    c.punch_stress.push_back(punch[i]);
    c.wall_stress.push_back(wall[i]);
    c.vol_axial.push_back(-syy[i]);
    c.vol_lateral.push_back(-sxx[i]);
    c.vol_out_of_plane.push_back(-szz[i]);
    c.ke_ie.push_back(keie[i]);
    c.time.push_back(time[i]);
    if (overlap) c.field_overlap.push_back((*overlap)[i]);
  }
  return c;
}

std::vector<double> ke_ie_beyond_affine(const StressStrainCurve& c, double mass_scaling) {
  const std::size_t n = c.size();
  if (c.kinetic.size() != n || c.internal.size() != n || c.mass.size() != n || c.punch_velocity.size() != n ||
      !(mass_scaling > 0.0) || !std::isfinite(mass_scaling))
    return c.ke_ie;
  std::vector<double> q(n);
  for (std::size_t i = 0; i < n; ++i) {
    const double v = c.punch_velocity[i];
    const double affine = mass_scaling * c.mass[i] * v * v / 6.0;
    q[i] = c.internal[i] > 0.0 ? std::max(0.0, c.kinetic[i] - affine) / c.internal[i] : c.ke_ie[i];
  }
  return q;
}

std::vector<std::size_t> points_in(const std::vector<double>& strain, double lo, double hi) {
  std::vector<std::size_t> idx;
  for (std::size_t i = 0; i < strain.size(); ++i) {
    if (strain[i] >= lo && strain[i] <= hi) idx.push_back(i);
  }
  return idx;
}

CurveDiscrepancy curve_discrepancy(const std::vector<double>& strain, const std::vector<double>& a,
                                   const std::vector<double>& b, double from) {
  CurveDiscrepancy d;
  double amax = 0, sum2 = 0, dmax = 0;
  for (std::size_t i = 0; i < strain.size(); ++i) {
    if (strain[i] < from || !std::isfinite(a[i]) || !std::isfinite(b[i])) continue;
    amax = std::max(amax, std::fabs(a[i]));
    const double r = a[i] - b[i];
    sum2 += r * r;
    dmax = std::max(dmax, std::fabs(r));
    ++d.points;
  }
  if (d.points == 0 || amax == 0) {
    d.rms_relative = d.max_relative = std::nan("");
    return d;
  }
  d.rms_relative = std::sqrt(sum2 / d.points) / amax;
  d.max_relative = dmax / amax;
  return d;
}

}  // namespace pbx
