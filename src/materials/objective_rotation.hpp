#pragma once
// Kinematics of one step for a hypoelastic update: the strain increment D dt and the incremental
// rotation of the Jaumann rate integrated with Hughes-Winget, R = (I - W dt/2)^-1 (I + W dt/2).
// Jaumann + Hughes-Winget is chosen over Green-Naghdi because it needs only L (not the polar
// decomposition of F), is exactly orthogonal, and its known artefact (stress oscillation in very
// large simple shear) is irrelevant at the few-percent strains of the paper.
// In plane strain (D = 2) W has one component, so R is the in-plane rotation given in closed form
// by the Cayley transform: cos = (1 - a^2)/(1 + a^2), sin = 2a/(1 + a^2), a = W_xy dt / 2.
#include "core/tensor.hpp"

namespace pbx {

template <int D>
struct StepRotation;

template <>
struct StepRotation<2> {
  double c = 1, s = 0;
  double c2 = 1, s2 = 0;  // cos and sin of the double angle: rotate (d, xy) of a deviator
  StepRotation() = default;
  StepRotation(const Mat<2>& L, double dt) {
    const double a = 0.25 * dt * (L(0, 1) - L(1, 0));
    const double inv = 1.0 / (1.0 + a * a);
    c = (1.0 - a * a) * inv;
    s = 2.0 * a * inv;
    c2 = c * c - s * s;
    s2 = 2.0 * c * s;
  }
  Sym3 apply(const Sym3& t) const {
    const double cc = c * c, ss = s * s, cs = c * s;
    return {cc * t.xx + 2.0 * cs * t.xy + ss * t.yy,
            ss * t.xx - 2.0 * cs * t.xy + cc * t.yy,
            t.zz,
            cs * (t.yy - t.xx) + (cc - ss) * t.xy,
            -s * t.zx + c * t.yz,
            c * t.zx + s * t.yz};
  }
};

template <>
struct StepRotation<3> {
  Mat3 R = Mat3::Identity();
  StepRotation() = default;
  StepRotation(const Mat<3>& L, double dt) : R(hughes_winget(skew_part(L), dt)) {}
  Sym3 apply(const Sym3& t) const { return rotate(t, R); }
};

// Strain increment D dt (3x3; plane strain has zero z components).
template <int D>
inline Sym3 strain_increment(const Mat<D>& L, double dt) {
  if constexpr (D == 2) {
    return {L(0, 0) * dt, L(1, 1) * dt, 0.0, 0.5 * (L(0, 1) + L(1, 0)) * dt, 0.0, 0.0};
  } else {
    return dt * sym_part(L);
  }
}

}  // namespace pbx
