// The run driver's measurements: one history row (forces from the exact contact impulses over the
// interval, energies, stresses, momentum), its columns, and the check that names a non-finite particle.
#include "run/runner.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>

#include <fmt/format.h>

namespace pbx {

namespace {
// The particle sums of a history row, strip by strip (StripBins::fold).
template <int D>
struct Sums {
  double vol = 0, mass = 0, ke = 0, v2max = 0;
  Sym3 sv;
  Vec<D> p = Vec<D>::Zero();
  Sums& operator+=(const Sums& o) {
    v2max = std::max(v2max, o.v2max);
    vol += o.vol;
    mass += o.mass;
    ke += o.ke;
    sv += o.sv;
    p += o.p;
    return *this;
  }
  template <class F>
  void each_double(F&& f) {
    for (double* x : {&vol, &mass, &ke, &v2max, &sv.xx, &sv.yy, &sv.zz, &sv.xy, &sv.yz, &sv.zx}) f(*x);
    for (int d = 0; d < D; ++d) f(p[d]);
  }
};
}  // namespace

template <int D>
Measurement Runner<D>::measure() {
  const auto& P = sc_.particles;
  // the books' sums of the steps since the last row (one gather in a decomposed run)
  solver_.settle_books();
  Measurement m;
  const double t = solver_.time();
  m.t = t;
  m.dt = solver_.dt();
  const double span = t - t_last_row_;
  m.body_force.resize(sc_.bodies.size());
  for (std::size_t b = 0; b < sc_.bodies.size(); ++b) {
    const Vec<D> f = span > 0 ? Vec<D>(sc_.bodies[b].impulse / span) : Vec<D>::Zero();
    m.body_force[b].assign(f.data(), f.data() + D);
  }

  const double fs = sc_.settings.mass_scaling;
  // strip by strip (StripBins::fold): the same bits on any thread and rank count
  const StripBins& strips = solver_.strips();
  Sums<D> s = strips.fold(Sums<D>{}, [&](long strip, Sums<D>& r) {
    for (long p = strips.begin[static_cast<std::size_t>(strip)]; p < strips.begin[static_cast<std::size_t>(strip + 1)];
         ++p) {
      r.vol += P.volume[p];
      r.mass += P.mass[p];
      const double v2 = P.v[p].squaredNorm();
      r.ke += 0.5 * fs * P.mass[p] * v2;
      r.v2max = std::max(r.v2max, v2);
      r.sv += P.volume[p] * P.stress[p];
      r.p += fs * P.mass[p] * P.v[p];
    }
  });
  m.mass = s.mass;
  m.momentum.assign(s.p.data(), s.p.data() + D);
  const Vec<D> vcm = s.p / (fs * s.mass);
  m.com_velocity.assign(vcm.data(), vcm.data() + D);
  double box = s.vol;
  if (sc_.die) {
    const Die& die = *sc_.die;
    const auto& punch = sc_.bodies[die.punch];
    const double d = -punch.displacement_at(t)[1];
    m.strain = d / die.height;
    m.punch_velocity = -punch.velocity_at(t)[1];
    m.punch_force = -m.body_force[die.punch][1];
    m.punch_stress = m.punch_force / die.punch_area();
    m.wall_left = m.body_force[die.left][0];
    m.wall_right = -m.body_force[die.right][0];
    m.wall_bottom = m.body_force[die.bottom][1];
    // the x walls' mean traction (in 3-D the front and back walls carry sigma_zz, as szz_Pa does)
    m.wall_stress = 0.5 * (m.wall_left + m.wall_right) / die.side_area(d);
    box = die.volume(d);
  }
  m.mean_stress = (1.0 / box) * s.sv;
  m.kinetic = s.ke;
  m.internal = solver_.internal_energy();
  m.dissipated = solver_.dissipated_energy();
  m.dissipated_parts = solver_.dissipated_by_material();
  m.dissipated_parts.push_back(solver_.friction_work());
  m.max_speed = std::sqrt(s.v2max);
  for (auto& b : sc_.bodies) punch_work_ += b.work;
  m.punch_work = punch_work_;
  m.ke_ie = m.internal > 0 ? m.kinetic / m.internal : 0.0;
  for (auto& b : sc_.bodies) {
    b.impulse.setZero();
    b.work = 0;
  }
  auto& tally = solver_.contact_tally();
  for (auto& mp : contact_pairs_) {
    const PairImpulse<D> pi = material_pair_impulse<D>(tally, sc_.contact, mp);
    const double inv = span > 0 ? 1.0 / span : 0.0;
    std::vector<double> f = {pi.normal * inv, pi.shear * inv};
    if (mp.first != mp.second)
      for (int d = 0; d < D; ++d) f.push_back(pi.on_first[d] * inv);
    m.pair_force.push_back(std::move(f));
  }
  tally.clear();
  if constexpr (D == 2) {
    if (overlap_)
      m.field_overlap.push_back(
          opt_.exchange
              ? overlap_->area(P, [&](std::vector<std::int32_t>& owner) { opt_.exchange->merge_field_owners(owner); })
              : overlap_->area(P));
  }
  if (sc_.contact.has_layers()) m.layer_energy.push_back(solver_.layer_energy());
  t_last_row_ = t;
  return m;
}

// "; particle p (material 'm') has a non-finite velocity" for the first particle whose state is
// not finite, or "" if every particle's is: names the culprit of a NaN found in the sums.
template <int D>
std::string Runner<D>::first_non_finite_particle() const {
  const auto& P = sc_.particles;
  for (std::size_t p = 0; p < P.size(); ++p) {
    const Sym3& st = P.stress[p];
    const char* what = !std::isfinite(P.mass[p])                                       ? "mass"
                       : !std::isfinite(P.volume[p])                                   ? "volume"
                       : !P.x[p].allFinite()                                           ? "position"
                       : !P.v[p].allFinite()                                           ? "velocity"
                       : !std::isfinite(st.xx + st.yy + st.zz + st.xy + st.yz + st.zx) ? "stress"
                                                                                       : nullptr;
    if (what)
      return fmt::format("; particle {} (material '{}') has a non-finite {}", p, sc_.material_names[P.material[p]],
                         what);
  }
  return "";
}

template <int D>
std::vector<double> Runner<D>::row_values(const Measurement& m, int) {
  std::vector<double> v = {0,
                           m.t,
                           m.dt,
                           m.strain,
                           m.punch_velocity,
                           m.punch_force,
                           m.punch_stress,
                           m.wall_left,
                           m.wall_right,
                           m.wall_bottom,
                           m.wall_stress,
                           m.mean_stress.xx,
                           m.mean_stress.yy,
                           m.mean_stress.zz,
                           m.mean_stress.xy,
                           m.kinetic,
                           m.internal,
                           m.dissipated,
                           m.punch_work,
                           m.ke_ie,
                           m.mass};
  for (double x : m.momentum) v.push_back(x);
  for (double x : m.com_velocity) v.push_back(x);
  for (auto& f : m.body_force)
    for (double x : f) v.push_back(x);
  for (auto& f : m.pair_force)
    for (double x : f) v.push_back(x);
  for (double x : m.field_overlap) v.push_back(x);
  for (double x : m.layer_energy) v.push_back(x);
  for (double x : m.dissipated_parts) v.push_back(x);
  v.push_back(m.max_speed);
  return v;
}

template Measurement Runner<2>::measure();
template std::string Runner<2>::first_non_finite_particle() const;
template std::vector<double> Runner<2>::row_values(const Measurement&, int);
template Measurement Runner<3>::measure();
template std::string Runner<3>::first_non_finite_particle() const;
template std::vector<double> Runner<3>::row_values(const Measurement&, int);

}  // namespace pbx
