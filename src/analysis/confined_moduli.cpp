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
  j["slope_Pa"] = f.slope;
  j["slope_std_error_Pa"] = f.slope_se;
  j["intercept_Pa"] = f.intercept;
  j["r2"] = f.r2;
  j["points"] = f.n;
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
  j["M_Pa"] = M;
  j["lambda_Pa"] = lambda;
  j["lambda_z_Pa"] = lambda_z;
  j["K_Pa"] = K;
  j["K_isotropic_Pa"] = K_isotropic;
  j["K_volume_average_Pa"] = K_volume;
  j["G_Pa"] = G;
  j["E_Pa"] = E;
  j["nu"] = nu;
  j["lateral_coefficient"] = lateral_coefficient;
  j["M_volume_average_Pa"] = axial_vol.slope;
  j["lambda_volume_average_Pa"] = lateral_vol.slope;
  Json fits = Json::object();
  fits["punch_stress"] = line_json(punch);
  fits["wall_stress"] = line_json(wall);
  fits["minus_syy"] = line_json(axial_vol);
  fits["minus_sxx"] = line_json(lateral_vol);
  fits["minus_szz"] = line_json(zz_vol);
  j["line_fits"] = fits;
  return j;
}

}  // namespace pbx
