#include "analysis/confined_moduli.hpp"

#include <cmath>

namespace pbx {

namespace {
LineFit fit_range(const std::vector<double>& x, const std::vector<double>& y, double lo, double hi) {
  std::vector<double> xs, ys;
  for (std::size_t i = 0; i < x.size(); ++i) {
    if (x[i] >= lo && x[i] <= hi && std::isfinite(y[i])) {
      xs.push_back(x[i]);
      ys.push_back(y[i]);
    }
  }
  return fit_line(xs, ys);
}
Json line_json(const LineFit& f) {
  Json j = Json::object();
  j.set("slope_Pa", f.slope);
  j.set("slope_std_error_Pa", f.slope_se);
  j.set("intercept_Pa", f.intercept);
  j.set("r2", f.r2);
  j.set("points", f.n);
  return j;
}
}  // namespace

ConfinedModuli confined_moduli(const StressStrainCurve& c, double lo, double hi) {
  ConfinedModuli m;
  m.punch = fit_range(c.strain, c.punch_stress, lo, hi);
  m.wall = fit_range(c.strain, c.wall_stress, lo, hi);
  m.axial_vol = fit_range(c.strain, c.vol_axial, lo, hi);
  m.lateral_vol = fit_range(c.strain, c.vol_lateral, lo, hi);
  m.zz_vol = fit_range(c.strain, c.vol_out_of_plane, lo, hi);
  std::vector<double> mean_vol(c.size());
  for (std::size_t i = 0; i < c.size(); ++i) {
    mean_vol[i] = (c.vol_axial[i] + c.vol_lateral[i] + c.vol_out_of_plane[i]) / 3.0;
  }
  m.K_volume = fit_range(c.strain, mean_vol, lo, hi).slope;
  m.M = m.punch.slope;
  m.lambda = m.wall.slope;
  m.lambda_z = m.zz_vol.slope;
  m.K = (m.M + m.lambda + m.lambda_z) / 3.0;
  m.K_isotropic = (m.M + 2.0 * m.lambda) / 3.0;
  m.G = 0.5 * (m.M - m.lambda);
  m.E = 9.0 * m.K * m.G / (3.0 * m.K + m.G);
  m.nu = (3.0 * m.K - 2.0 * m.G) / (2.0 * (3.0 * m.K + m.G));
  m.lateral_coefficient = m.lambda / m.M;
  return m;
}

ConfinedModuli confined_moduli_volume_average(const StressStrainCurve& c, double lo, double hi) {
  StressStrainCurve v = c;
  v.punch_stress = c.vol_axial;
  v.wall_stress = c.vol_lateral;
  return confined_moduli(v, lo, hi);
}

Json ConfinedModuli::to_json() const {
  Json j = Json::object();
  j.set("M_Pa", M);
  j.set("lambda_Pa", lambda);
  j.set("lambda_z_Pa", lambda_z);
  j.set("K_Pa", K);
  j.set("K_isotropic_Pa", K_isotropic);
  j.set("K_volume_average_Pa", K_volume);
  j.set("G_Pa", G);
  j.set("E_Pa", E);
  j.set("nu", nu);
  j.set("lateral_coefficient", lateral_coefficient);
  j.set("M_volume_average_Pa", axial_vol.slope);
  j.set("lambda_volume_average_Pa", lateral_vol.slope);
  Json fits = Json::object();
  fits.set("punch_stress", line_json(punch));
  fits.set("wall_stress", line_json(wall));
  fits.set("minus_syy", line_json(axial_vol));
  fits.set("minus_sxx", line_json(lateral_vol));
  fits.set("minus_szz", line_json(zz_vol));
  j.set("line_fits", fits);
  return j;
}

}  // namespace pbx
