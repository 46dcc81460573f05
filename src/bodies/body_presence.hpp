#pragma once
// The rigid bodies' presence on the grid (the sum of their particles' weights at each node, which
// the rigid contact stage reads) and the ascending list of the nodes where any body is present.
// A static body's presence is computed once and replayed; a moving one's every step.
#include <algorithm>
#include <cstdint>
#include <iterator>
#include <utility>
#include <vector>

#include <fmt/format.h>

#include "bodies/rigid_body.hpp"
#include "core/error.hpp"
#include "grid/grid.hpp"
#include "grid/shape.hpp"

namespace pbx {

template <int D>
class BodyPresence {
 public:
  // Fills grid.presence for every body and lists the nodes. step and t name the step in the error
  // thrown when a moving body has left the grid.
  template <Kernel K>
  void scatter(Grid<D>& g, const std::vector<RigidBody<D>>& bodies, const HalfWidth& a, long step, double t) {
    const double inv_h = 1.0 / g.h;
    const long nn = g.nodes();
    if (static_.size() != bodies.size()) static_.assign(bodies.size(), {});
    std::fill(g.presence.begin(), g.presence.end(), 0.0);
    // the nodes where a moving body is present lie in [lo, hi] (a punch: a few node rows)
    long lo = nn, hi = -1;
    for (std::size_t b = 0; b < bodies.size(); ++b) {
      const auto& body = bodies[b];
      double* gm = g.presence.data() + (body.field - g.deformable) * nn;
      auto& cache = static_[b];
      if (!body.moving() && !cache.empty()) {
        for (auto& [i, S] : cache) gm[i] += S;
        continue;
      }
      for (std::size_t k = 0; k < body.x.size(); ++k) {
        const Vec<D>& x = body.x[k];
        const Stencil<D> st = make_stencil<D, K>(x, g.origin, inv_h, a);
        // a moving body can leave the grid (the scene checks its particles at t = 0 only); its
        // presence would then wrap to the next node row or be written past the end of the array
        for (int d = 0; d < D; ++d)
          if (st.base[d] < 0 || st.base[d] + 2 >= g.n[d])
            throw InstabilityError(
                fmt::format("step {} (t = {:.6g} s): rigid body '{}' left the grid (its particle {} at "
                            "{:.6g} m along axis {}): enlarge the grid or stop the body earlier",
                            step, t, body.name, k, x[d], d));
        for_each_node<D>(st, g.stride, [&](long i, double S, const Vec<D>&) {
          gm[i] += S;
          lo = std::min(lo, i);
          hi = std::max(hi, i);
        });
      }
      if (!body.moving()) {
        for (long i = 0; i < nn; ++i)
          if (gm[i] > 0) cache.emplace_back(i, gm[i]);
        static_listed_ = false;  // rebuilt below with this body's nodes
      }
    }
    list_nodes(g, bodies, lo, hi);
  }

  // The nodes where any body is present, ascending (the rigid contact stage visits only these).
  const std::vector<long>& nodes() const { return nodes_; }
  // A static body's presence: (node, weight) pairs, once scattered.
  const std::vector<std::pair<long, double>>& static_presence(std::size_t body) const { return static_[body]; }

 private:
  // The static bodies' nodes (listed once) merged with the moving bodies' nodes found in [lo, hi].
  // The stage visited every node of the grid for every body before (≈ 2 % of the die benchmark).
  void list_nodes(const Grid<D>& g, const std::vector<RigidBody<D>>& bodies, long lo, long hi) {
    const long nn = g.nodes();
    std::vector<long> moving;
    for (long i = lo; i <= hi; ++i)
      for (std::size_t b = 0; b < bodies.size(); ++b)
        if (bodies[b].moving() && g.rigid_presence(bodies[b].field, i) > 0) {
          moving.push_back(i);
          break;
        }
    if (!static_listed_) {
      static_nodes_.clear();
      std::vector<std::uint8_t> at(static_cast<std::size_t>(nn), 0);
      for (std::size_t b = 0; b < bodies.size(); ++b)
        if (!bodies[b].moving())
          for (const auto& [i, S] : static_[b]) at[static_cast<std::size_t>(i)] = 1;
      for (long i = 0; i < nn; ++i)
        if (at[static_cast<std::size_t>(i)]) static_nodes_.push_back(i);
      static_listed_ = true;
    }
    nodes_.clear();
    std::set_union(static_nodes_.begin(), static_nodes_.end(), moving.begin(), moving.end(),
                   std::back_inserter(nodes_));
  }

  std::vector<std::vector<std::pair<long, double>>> static_;  // per body, static ones only
  std::vector<long> nodes_, static_nodes_;
  bool static_listed_ = false;
};

}  // namespace pbx
