#pragma once
// Compact storage of a deviatoric (traceless) tensor in a particle's history. In plane strain a
// deviatoric tensor built from in-plane increments and in-plane rotations has zero yz, zx and
// zz = -(xx + yy), so three numbers suffice: m = (xx + yy)/2, d = (xx - yy)/2 and xy, chosen
// because an in-plane rotation by theta leaves m unchanged and turns (d, xy) by 2 theta, and
// |t|^2 = 6 m^2 + 2 d^2 + 2 xy^2. In 3D all six components are kept.
#include <string>
#include <vector>

#include "core/tensor.hpp"

namespace pbx {

template <int D>
struct DeviatoricStorage {
  static constexpr int size = (D == 2) ? 3 : 6;
  static Sym3 load(const double* h) {
    if constexpr (D == 2) {
      return {h[0] + h[1], h[0] - h[1], -2.0 * h[0], h[2], 0.0, 0.0};
    } else {
      return {h[0], h[1], h[2], h[3], h[4], h[5]};
    }
  }
  static void store(const Sym3& s, double* h) {
    if constexpr (D == 2) {
      h[0] = 0.5 * (s.xx + s.yy), h[1] = 0.5 * (s.xx - s.yy), h[2] = s.xy;
    } else {
      h[0] = s.xx, h[1] = s.yy, h[2] = s.zz, h[3] = s.xy, h[4] = s.yz, h[5] = s.zx;
    }
  }
  static void names(const std::string& base, std::vector<std::string>& out) {
    if constexpr (D == 2) {
      for (const char* c : {"mean_xx_yy", "half_diff_xx_yy", "xy"}) out.push_back(base + "_" + c);
    } else {
      for (const char* c : {"xx", "yy", "zz", "xy", "yz", "zx"}) out.push_back(base + "_" + c);
    }
  }
};

}  // namespace pbx
