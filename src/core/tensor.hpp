#pragma once
// Small fixed-size vectors and tensors. Dim is a template parameter everywhere (2 = plane strain,
// 3 = full 3D); stresses are always stored as symmetric 3x3 so plane strain keeps sigma_zz.
#include <Eigen/Dense>

namespace pbx {

template <int D>
using Vec = Eigen::Matrix<double, D, 1>;
template <int D>
using Mat = Eigen::Matrix<double, D, D>;
using Mat3 = Eigen::Matrix3d;
using Vec3 = Eigen::Vector3d;

// Symmetric 3x3 tensor stored as (xx, yy, zz, xy, yz, zx).
struct Sym3 {
  double xx = 0, yy = 0, zz = 0, xy = 0, yz = 0, zx = 0;

  static Sym3 from(const Mat3& m) {
    return {m(0, 0), m(1, 1), m(2, 2), 0.5 * (m(0, 1) + m(1, 0)), 0.5 * (m(1, 2) + m(2, 1)), 0.5 * (m(2, 0) + m(0, 2))};
  }
  Mat3 mat() const {
    Mat3 m;
    m << xx, xy, zx, xy, yy, yz, zx, yz, zz;
    return m;
  }
  double trace() const { return xx + yy + zz; }
  double mean() const { return trace() / 3.0; }
  Sym3 dev() const {
    const double p = mean();
    return {xx - p, yy - p, zz - p, xy, yz, zx};
  }
  // Double contraction a:b, counting the off-diagonal terms twice.
  double ddot(const Sym3& b) const {
    return xx * b.xx + yy * b.yy + zz * b.zz + 2.0 * (xy * b.xy + yz * b.yz + zx * b.zx);
  }
  double norm() const { return std::sqrt(ddot(*this)); }
  // von Mises equivalent of this tensor's deviator, sqrt(3/2 s:s).
  double von_mises() const {
    const Sym3 s = dev();
    return std::sqrt(1.5 * s.ddot(s));
  }
  Sym3& operator+=(const Sym3& b) {
    xx += b.xx;
    yy += b.yy;
    zz += b.zz;
    xy += b.xy;
    yz += b.yz;
    zx += b.zx;
    return *this;
  }
  Sym3& operator*=(double a) {
    xx *= a;
    yy *= a;
    zz *= a;
    xy *= a;
    yz *= a;
    zx *= a;
    return *this;
  }
  friend Sym3 operator+(Sym3 a, const Sym3& b) { return a += b; }
  friend Sym3 operator-(const Sym3& a, const Sym3& b) {
    return {a.xx - b.xx, a.yy - b.yy, a.zz - b.zz, a.xy - b.xy, a.yz - b.yz, a.zx - b.zx};
  }
  friend Sym3 operator*(double a, Sym3 b) { return b *= a; }
  static Sym3 identity(double a = 1.0) { return {a, a, a, 0, 0, 0}; }
};

// Zero-padded 3x3 copy of a DxD tensor (plane strain: the z row and column are zero).
template <int D>
inline Mat3 embed3(const Mat<D>& a) {
  if constexpr (D == 3) {
    return a;
  } else {
    Mat3 m = Mat3::Zero();
    m.template topLeftCorner<D, D>() = a;
    return m;
  }
}

// Symmetric part D = sym(L) and spin W = skew(L) of a velocity gradient.
inline Sym3 sym_part(const Mat3& L) { return Sym3::from(L); }
inline Mat3 skew_part(const Mat3& L) { return 0.5 * (L - L.transpose()); }

// Hughes-Winget incremental rotation R = (I - W dt/2)^-1 (I + W dt/2): exactly orthogonal, so a
// stress rotated by it keeps its invariants (objective Jaumann-type update).
inline Mat3 hughes_winget(const Mat3& W, double dt) {
  if (W(0, 2) == 0.0 && W(1, 2) == 0.0) {
    // in-plane spin (plane strain): closed form, a rotation by 2 atan(a), a = W_xy dt / 2
    const double a = 0.5 * dt * W(0, 1), d = 1.0 / (1.0 + a * a);
    Mat3 R = Mat3::Identity();
    R(0, 0) = R(1, 1) = (1.0 - a * a) * d;
    R(0, 1) = 2.0 * a * d;
    R(1, 0) = -2.0 * a * d;
    return R;
  }
  const Mat3 I = Mat3::Identity();
  return (I - 0.5 * dt * W).inverse() * (I + 0.5 * dt * W);
}
inline Sym3 rotate(const Sym3& s, const Mat3& R) { return Sym3::from(R * s.mat() * R.transpose()); }

}  // namespace pbx
