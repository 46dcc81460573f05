#pragma once
// The particle <-> grid transfers of one particle, given its stencil: the P2G scatter (mass,
// momentum, mass-centre offset, volume gradient, internal and body force) and the G2P gather
// (PIC velocity, FLIP increment, velocity gradient). The transfer stages (Solver::p2g, g2p) and the
// fused particle pass (Solver::g2p_update_p2g) call the same kernels, so a node receives the same
// bits whichever path made it.
#include <array>
#include <cstdint>

#include "contact/layer_data.hpp"
#include "grid/grid.hpp"
#include "grid/shape.hpp"
#include "particles/particles.hpp"

namespace pbx {

// In-plane (D x D) block of a stored 3x3 Cauchy stress.
template <int D>
inline Mat<D> in_plane(const Sym3& s) {
  if constexpr (D == 2) {
    Mat<2> m;
    m << s.xx, s.xy, s.xy, s.yy;
    return m;
  } else {
    return s.mat();
  }
}

// One node row of the binder-layer sums (2-D), out of line so the common path stays small. A
// particle that is not bonded carries no bond flag, 1/t or contact normal (all zero), so it adds
// only its reference position and F: most particles lie away from a grain-grain contact, and
// adding their zeros was a fifth of the scatter on the paper specimen.
template <int D>
inline void scatter_layer_row(LayerData<D>& l, const Vec<D>& origin, const Mat<D>& F, std::uint32_t p, long off, long r,
                              const std::array<double, 3>& wx, double mj, const Vec<D>& normal) {
  const LayerParticles<D>& lp = l.particles;
  LayerSums<D>& s = l.sums;
  const Vec<D> xj = mj * (lp.X0[p] - origin);
  const Mat<D> fj = mj * F;
  for (int i = 0; i < 3; ++i) {
    s.mref[off + r + i] += wx[i] * xj;
    s.mdef[off + r + i] += wx[i] * fj;
  }
  if (!lp.bonded[p]) return;
  const double bj = mj * lp.bonded[p];
  const double tj = mj * lp.inv_t[p];
  const Vec<D> nj = mj * normal;
  for (int i = 0; i < 3; ++i) {
    s.mbond[off + r + i] += wx[i] * bj;
    s.minvt[off + r + i] += wx[i] * tj;
    s.mnorm[off + r + i] += wx[i] * nj;
  }
}

template <int D>
struct Scatter {
  Grid<D>& g;
  const Particles<D>& P;
  double fs;                 // mass scaling
  Vec<D> grav;               // gravity, m/s^2
  bool gravity;              // grav is not zero
  bool mass_momentum;        // scatter mass, momentum (and offsets, gradients)
  bool forces;               // scatter internal and body forces
  bool offsets;              // mass-centre offsets (rigid-body contact gate, field position check)
  bool gradients;            // volume gradients (contact normals between several fields)
  bool layers;               // reference positions, F and bond flags (binder_layer contact law)
  bool offsets_for_contact;  // the field contact reads the offsets too (binder_layer, position check)
  // with offsets: only particles whose stencil base node is marked here scatter them for the
  // rigid-body gate (2-D; null: every particle)
  const std::uint8_t* offset_bases = nullptr;
  // only particles whose stencil base node is marked here scatter what the field contact reads
  // (gradients, binder-layer sums, and the offsets when it reads them): their stencils meet the
  // nodes where two or more fields can be present this step (Solver::mark_contact_bases; 2-D;
  // null: every particle)
  const std::uint8_t* contact_bases = nullptr;
  // with layers: the binder_layer data the sums are built from and into
  LayerData<D>* layer_data = nullptr;

  [[gnu::always_inline]] void operator()(std::uint32_t p, const Stencil<D>& st) const {
    const long off = P.field[p] * g.nodes();  // a product of two longs in 2-D
    const double m = P.mass[p] * fs;
    const Vec<D> mv = m * P.v[p];
    const Mat<D> sv = -P.volume[p] * in_plane<D>(P.stress[p]);
    const Vec<D> fext = P.mass[p] * grav;  // body force acts on the physical mass
    double* gm = g.mass.data() + off;
    Vec<D>* gp = g.mom.data() + off;
    Vec<D>* gf = g.force.data() + off;
    Vec<D>* go = g.moff.data() + off;
    Vec<D>* gg = g.vgrad.data() + off;
    const double vol = P.volume[p];
    const Vec<D> xs = P.x[p] - g.origin;
    if constexpr (D == 2) {
      // Tensor-product form of the 3 x 3 stencil, S = wx_i wy_j, G = (gx_i wy_j, wx_i gy_j):
      // per node row j the particle's contributions are scaled by the row factors once, then
      // by the x factors. Every nodal sum keeps its order.
      // The weights and the run-constant switches are copied into locals first: a store into a
      // nodal array may alias the stencil and this functor as far as the compiler knows, so it
      // reloaded every weight and re-tested every switch after each of the 63 nodal stores.
      const double wx0 = st.w[0][0], wx1 = st.w[0][1], wx2 = st.w[0][2];
      const double gx0 = st.g[0][0], gx1 = st.g[0][1], gx2 = st.g[0][2];
      const double wys[3] = {st.w[1][0], st.w[1][1], st.w[1][2]};
      const double gys[3] = {st.g[1][0], st.g[1][1], st.g[1][2]};
      const long row_stride = g.stride[1];
      const long b0 = st.base[0] * g.stride[0] + st.base[1] * row_stride;
      const bool near_contact = contact_bases == nullptr || contact_bases[b0] != 0;
      const bool do_mass = mass_momentum, do_forces = forces, do_gradients = gradients && near_contact,
                 do_gravity = gravity, do_layers = layers && near_contact,
                 do_offsets = offsets && ((offset_bases == nullptr || offset_bases[b0] != 0) ||
                                          (offsets_for_contact && near_contact));
      // the particle's contact normal, mapped with F^-T (binder_layer runs only): once per particle
      const Vec<D> normal = do_layers && layer_data->particles.bonded[p]
                                ? Vec<D>(P.F[p].inverse().transpose() * layer_data->particles.N0[p])
                                : Vec<D>::Zero();
      const Vec<D> s0 = sv.col(0), s1 = sv.col(1);
      for (int j = 0; j < 3; ++j) {
        const long r = b0 + j * row_stride;
        const double wy = wys[j], gy = gys[j];
        if (do_mass) {
          const double mj = wy * m;
          const Vec<D> pj = wy * mv;
          gm[r] += wx0 * mj;
          gm[r + 1] += wx1 * mj;
          gm[r + 2] += wx2 * mj;
          gp[r] += wx0 * pj;
          gp[r + 1] += wx1 * pj;
          gp[r + 2] += wx2 * pj;
          if (do_offsets) {
            const Vec<D> oj = mj * xs;
            go[r] += wx0 * oj;
            go[r + 1] += wx1 * oj;
            go[r + 2] += wx2 * oj;
          }
          if (do_gradients) {
            gg[r] += vol * Vec<D>(gx0 * wy, wx0 * gy);
            gg[r + 1] += vol * Vec<D>(gx1 * wy, wx1 * gy);
            gg[r + 2] += vol * Vec<D>(gx2 * wy, wx2 * gy);
          }
          if (do_layers) scatter_layer_row<D>(*layer_data, g.origin, P.F[p], p, off, r, {wx0, wx1, wx2}, mj, normal);
        }
        if (do_forces) {
          const Vec<D> fa = wy * s0, fb = gy * s1;
          gf[r] += gx0 * fa + wx0 * fb;
          gf[r + 1] += gx1 * fa + wx1 * fb;
          gf[r + 2] += gx2 * fa + wx2 * fb;
          if (do_gravity) {
            const Vec<D> fj = wy * fext;
            gf[r] += wx0 * fj;
            gf[r + 1] += wx1 * fj;
            gf[r + 2] += wx2 * fj;
          }
        }
      }
    } else {
      // one node loop per quantity, the run-constant switches tested once per particle
      if (mass_momentum) {
        for_each_node<D>(st, g.stride, [&](long i, double S, const Vec<D>&) {
          gm[i] += S * m;
          gp[i] += S * mv;
        });
        if (offsets) for_each_node<D>(st, g.stride, [&](long i, double S, const Vec<D>&) { go[i] += (S * m) * xs; });
        if (gradients) for_each_node<D>(st, g.stride, [&](long i, double, const Vec<D>& G) { gg[i] += vol * G; });
        if (layers) {
          const LayerParticles<D>& lp = layer_data->particles;
          LayerSums<D>& ls = layer_data->sums;
          for_each_node<D>(st, g.stride, [&](long i, double S, const Vec<D>&) {
            const double sm = S * m;
            ls.mref[off + i] += sm * (lp.X0[p] - g.origin);
            ls.mdef[off + i] += sm * P.F[p];
          });
          if (lp.bonded[p]) {  // (as in 2-D: the rest are zero for a particle that is not bonded)
            const Vec<D> normal = P.F[p].inverse().transpose() * lp.N0[p];
            for_each_node<D>(st, g.stride, [&](long i, double S, const Vec<D>&) {
              const double sm = S * m;
              ls.mbond[off + i] += sm * lp.bonded[p];
              ls.minvt[off + i] += sm * lp.inv_t[p];
              ls.mnorm[off + i] += sm * normal;
            });
          }
        }
      }
      if (forces) {
        for_each_node<D>(st, g.stride, [&](long i, double S, const Vec<D>& G) {
          gf[i] += sv * G;
          if (gravity) gf[i] += S * fext;
        });
      }
    }
  }
};

// What the gather gives: PIC velocity, FLIP increment and (when asked) the velocity gradient.
template <int D>
struct Gathered {
  Vec<D> vpic = Vec<D>::Zero(), dv = Vec<D>::Zero();
  Mat<D> L = Mat<D>::Zero();
};

// G2P gather from the step's final nodal velocities `vel` and increments `dvel` of field `off`.
template <int D>
inline Gathered<D> gather(const Grid<D>& g, long off, const Stencil<D>& st, bool gradient) {
  const Vec<D>* gv = g.vel.data() + off;
  const Vec<D>* gdv = g.dvel.data() + off;
  Gathered<D> r;
  if constexpr (D == 2) {
    // Tensor-product form: per node row j the x-sums a_j = sum_i wx_i v_ij,
    // b_j = sum_i gx_i v_ij and c_j = sum_i wx_i dv_ij; then v = sum_j wy_j a_j,
    // dv = sum_j wy_j c_j and L = sum v (x) G = [sum_j wy_j b_j | sum_j gy_j a_j].
    const auto& wx = st.w[0];
    const auto& gx = st.g[0];
    const long b0 = st.base[0] * g.stride[0] + st.base[1] * g.stride[1];
    for (int j = 0; j < 3; ++j) {
      const long rr = b0 + j * g.stride[1];
      const double wy = st.w[1][j];
      const Vec<D> aj = wx[0] * gv[rr] + wx[1] * gv[rr + 1] + wx[2] * gv[rr + 2];
      const Vec<D> cj = wx[0] * gdv[rr] + wx[1] * gdv[rr + 1] + wx[2] * gdv[rr + 2];
      r.vpic += wy * aj;
      r.dv += wy * cj;
      if (gradient) {
        const Vec<D> bj = gx[0] * gv[rr] + gx[1] * gv[rr + 1] + gx[2] * gv[rr + 2];
        r.L.col(0) += wy * bj;
        r.L.col(1) += st.g[1][j] * aj;
      }
    }
  } else if (gradient) {
    for_each_node<D>(st, g.stride, [&](long i, double S, const Vec<D>& G) {
      r.vpic += S * gv[i];
      r.dv += S * gdv[i];
      r.L += gv[i] * G.transpose();
    });
  } else {
    for_each_node<D>(st, g.stride, [&](long i, double S, const Vec<D>&) {
      r.vpic += S * gv[i];
      r.dv += S * gdv[i];
    });
  }
  return r;
}

}  // namespace pbx
