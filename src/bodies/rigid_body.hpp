#pragma once
// Rigid bodies (die walls, punch): a cloud of rigid particles on their own velocity field, moving
// with a prescribed velocity. Contact with deformable fields uses the body's specified outward
// normal (no gradient noise at flat walls). Reactions are accumulated from the exact momentum
// impulses the contact applies to the specimen, so force = rate of momentum exchanged.
#include <cmath>
#include <string>
#include <vector>

#include "core/tensor.hpp"

namespace pbx {

enum class RigidContact {
  unilateral,  // acts only while the specimen approaches (die walls, punch)
  stick        // holds the specimen's nodal velocity to the body's (a clamped end)
};

// Velocity history v(t) = v_final * r(t): r rises smoothly (1 - cos) over t_ramp, then stays 1.
struct VelocityRamp {
  double t_ramp = 0;  // s; 0 = constant velocity from the start
  double factor(double t) const {
    if (t_ramp <= 0 || t >= t_ramp) return 1.0;
    return 0.5 * (1.0 - std::cos(M_PI * t / t_ramp));
  }
  // Integral of factor from 0 to t (displacement per unit final speed), s.
  double integral(double t) const {
    if (t_ramp <= 0) return t;
    if (t < t_ramp) return 0.5 * (t - t_ramp / M_PI * std::sin(M_PI * t / t_ramp));
    return 0.5 * t_ramp + (t - t_ramp);
  }
};

template <int D>
struct RigidBody {
  std::string name;
  int field = -1;                    // grid field index of this body
  std::vector<Vec<D>> x0;            // rigid particle positions at t = 0, m
  std::vector<Vec<D>> x;             // current positions, m
  Vec<D> velocity = Vec<D>::Zero();  // final prescribed velocity, m/s
  VelocityRamp ramp;
  Vec<D> normal = Vec<D>::Zero();  // unit outward normal (from the body into the specimen)
  double friction = 0;             // Coulomb coefficient against the specimen
  RigidContact contact = RigidContact::unilateral;
  // Position of the body's contact face along `normal` at t = 0 (x . n), m. Contact acts only at
  // nodes at or behind the face: a node a fraction of a cell in front of it belongs to the
  // specimen alone, which removes the one-cell-early contact of kernel-overlap detection.
  double face0 = 0;
  // A node in front of the face also takes part when the mass centre of the specimen field near
  // it lies within `cutoff` cells of the face (Lemiale, Hurmane & Nairn 2010 position check;
  // 0.8 is Nairn's recommendation for uGIMP with 2 particles per cell per axis).
  double cutoff = 0.8;
  bool moving() const { return velocity.squaredNorm() > 0; }
  double face_at(double t) const { return face0 + displacement_at(t).dot(normal); }

  Vec<D> velocity_at(double t) const { return velocity * ramp.factor(t); }
  Vec<D> displacement_at(double t) const { return velocity * ramp.integral(t); }
  void move_to(double t) {
    const Vec<D> u = displacement_at(t);
    for (std::size_t k = 0; k < x.size(); ++k) x[k] = x0[k] + u;
  }

  // Accumulated over the current reporting interval (reset by the solver's observer):
  Vec<D> impulse = Vec<D>::Zero();  // impulse given BY the body TO the specimen, N s (per m)
  double work = 0;                  // work done by the body on the specimen, J (per m)
};

}  // namespace pbx
