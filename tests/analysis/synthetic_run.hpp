#pragma once
// Synthetic run directories in the format of `pbxmpm run`, for testing the analysis without the
// engine: confined compression of an elastic solid (K, G) that softens onto the paper's Eq. 14
// plateau, sigma = min(M e, sigma_c (A e% + B e%^n)), with the lateral stress k0 = lambda/M times
// the axial one. The volume averages differ from the boundary stresses by `vol_bias` (relative).
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>

#include <fmt/format.h>

namespace pbx::test {

struct SyntheticRun {
  double K = 2.79e9, G = 1.30e9;
  double strength_scale = 32.8e6;  // sigma_c of the plateau law
  double A = -0.1206, B = 1.084, n = 0.2467;
  bool elastic_only = false;
  double szz_factor = 1.0;  // sigma_zz = szz_factor * sigma_xx
  double max_strain = 0.04;
  int rows = 801;
  double ramp_strain = 0.0005;
  double vol_bias = 0.01;
  double temperature_K = 293;
  double density_kg_m3 = 1787;
  double porosity = 0.0798;
  std::string status = "finished";
  std::string group = "temperature";
  int seed = 1;
  // >= 0: a field_overlap_m2_per_m column growing by this share of the compaction (box area the
  // punch took) from 1e-12 m^2 per m
  double overlap_share = -1;
  // KE/IE: 0.3 inside the ramp, then ke_ie_bump up to strain ke_ie_bump_until, then 0.01
  double ke_ie_bump = 0.01, ke_ie_bump_until = 0;
  // > 0: a mass_kg_per_m column of this (unscaled) mass, and the kinetic energy of the affine motion
  // behind the punch, f m v^2 / 6 (f = run.json's mass scaling, 100), added to the kinetic energy
  double affine_mass = 0;
  // the punch reaction rings: punch stress (only) times 1 + ring_amplitude sin(2 pi e / ring_period)
  double ring_amplitude = 0, ring_period = 1e-3;
  // Energies: punch work W = integral of the punch stress over the box area's compaction, stress
  // work 0.9 W (+ energy_gain W from strain energy_gain_from on), kinetic energy ke_ie x stress work.
  double energy_gain = 0, energy_gain_from = 0.003;
};

inline double synthetic_axial(const SyntheticRun& s, double e) {
  const double M = s.K + 4.0 * s.G / 3.0;
  if (s.elastic_only || e <= 0) return M * e;
  const double pct = 100.0 * e;
  return std::min(M * e, s.strength_scale * (s.A * pct + s.B * std::pow(pct, s.n)));
}

inline void write_synthetic_run(const std::filesystem::path& dir, const SyntheticRun& s) {
  std::filesystem::create_directories(dir);
  const double M = s.K + 4.0 * s.G / 3.0, lambda = s.K - 2.0 * s.G / 3.0, k0 = lambda / M;
  std::ofstream h(dir / "history.csv");
  h << "step,t_s,dt_s,strain,punch_velocity_m_s,punch_force_N_per_m,punch_stress_Pa,wall_left_force_N_per_m,"
       "wall_right_force_N_per_m,wall_bottom_force_N_per_m,wall_stress_Pa,sxx_Pa,syy_Pa,szz_Pa,sxy_Pa,"
       "kinetic_J_per_m,internal_J_per_m,dissipated_J_per_m,punch_work_J_per_m,ke_ie,extra_contact_N_per_m"
    << (s.overlap_share >= 0 ? ",field_overlap_m2_per_m" : "") << (s.affine_mass > 0 ? ",mass_kg_per_m\n" : "\n");
  double work = 0, e_prev = 0, sa_prev = 0;
  for (int i = 0; i < s.rows; ++i) {
    const double e = s.max_strain * i / (s.rows - 1);
    const double t = e / 250.0;
    const double sa = synthetic_axial(s, e), sl = k0 * sa;
    const double sp = sa * (1.0 + s.ring_amplitude * std::sin(2.0 * M_PI * e / s.ring_period));
    const double ke_ie = e < s.ramp_strain ? 0.3 : e < s.ke_ie_bump_until ? s.ke_ie_bump : 0.01;
    work += 0.5 * (sa + sa_prev) * (e - e_prev) * 1e-3 * 1.2e-3;  // J/m: box 1 x 1.2 mm
    e_prev = e, sa_prev = sa;
    const double ie = (0.9 + (e >= s.energy_gain_from ? s.energy_gain : 0.0)) * work;
    const double ke = ke_ie * ie + (s.affine_mass > 0 ? 100.0 * s.affine_mass * 0.3 * 0.3 / 6.0 : 0.0);
    h << fmt::format(
        "{},{:.9g},1e-9,{:.9g},0.3,{:.9g},{:.9g},{:.9g},{:.9g},{:.9g},{:.9g},{:.9g},{:.9g},{:.9g},0,{:.9g},{:.9g},0,{:."
        "9g},{},0\n",
        i * 100, t, e, sp * 1e-3, sp, sl * 1.2e-3, sl * 1.2e-3, sa * 1e-3, sl, -sl * (1 + s.vol_bias),
        -sa * (1 + s.vol_bias), -s.szz_factor * sl * (1 + s.vol_bias), ke, ie, work,
        s.affine_mass > 0 && ie > 0 ? ke / ie : ke_ie);
    if (s.overlap_share >= 0) {
      h.seekp(-1, std::ios_base::cur);  // replace the newline
      h << fmt::format(",{:.12g}\n", 1e-12 + s.overlap_share * e * 1e-3 * 1.2e-3);
    }
    if (s.affine_mass > 0) {
      h.seekp(-1, std::ios_base::cur);
      h << fmt::format(",{:.12g}\n", s.affine_mass);
    }
  }
  std::ofstream r(dir / "run.json");
  r << fmt::format(R"({{"status": "{}", "code_version": "synthetic", "temperature_K": {}, "ramp_strain": {},
 "mass_scaling": 100, "specimen": {{"density_kg_m3": {}, "porosity": {}, "tmd_kg_m3": 1942, "width_m": 1e-3,
 "height_m": 1.2e-3}}, "study": {{"group": "{}", "temperature_K": {}, "density_g_cm3": {}, "seed": {}}},
 "deck": {{"run": {{"title": "synthetic confined compression"}}}}, "unknown_extra": [1, 2, {{"a": null}}]}})",
                   s.status, s.temperature_K, s.ramp_strain, s.density_kg_m3, s.porosity, s.group, s.temperature_K,
                   s.density_kg_m3 / 1e3, s.seed);
}

}  // namespace pbx::test
