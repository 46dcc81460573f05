#pragma once
// The die of the paper (Fig. 1a): the specimen in [0, width] x [0, height] between three fixed
// walls and a punch moving down at punch_velocity; walls and punch are rigid bodies (indices into
// Scene::bodies). In 3-D the cavity is [0, width] x [0, height] x [0, depth], with a front (z = 0)
// and a back wall (z = depth) beside the left and right ones. The die owns the punch timing, so the
// scene (end time, the punch's ramp) and the study's phase moduli (study/run_phases.cpp, the
// loading time) read one formula.

namespace pbx {

// die.ramp_strain when a deck does not give it
inline constexpr double kDefaultRampStrain = 0.002;

struct Die {
  double width = 0, height = 0;  // m (initial specimen box)
  double depth = 0;              // m, 3-D only (0: a 2-D die, whose quantities are per metre of depth)
  double punch_velocity = 0;     // m/s, magnitude (the punch moves in -y)
  double ramp_strain = 0;        // strain over which the punch speed ramps up smoothly
  int left = -1, right = -1, bottom = -1, punch = -1;
  int front = -1, back = -1;  // 3-D only

  // Whether body index b is one of the die's walls or its punch.
  bool owns(int b) const {
    return b >= 0 && (b == left || b == right || b == bottom || b == punch || b == front || b == back);
  }
  // The punch face's area (m^2; in 2-D m per metre of depth), an x wall's area and the cavity's
  // volume (m^3; in 2-D m^2 per metre of depth) at punch displacement d (m).
  double punch_area() const { return width * per_depth(); }
  double side_area(double d) const { return (height - d) * per_depth(); }
  double volume(double d = 0) const { return width * (height - d) * per_depth(); }
  // the depth the areas and volume are taken over: the cavity's in 3-D, one metre in 2-D
  double per_depth() const { return depth > 0 ? depth : 1.0; }

  // The punch's speed rises as (1 - cos) over the ramp time, moving ramp_strain x height meanwhile
  // (at half its final speed on average), then stays at punch_velocity. s.
  double ramp_time() const { return punch_velocity > 0 ? 2.0 * ramp_strain * height / punch_velocity : 0.0; }
  // When the nominal strain e >= ramp_strain is reached: t_ramp + (e - ramp) H / v, i.e. (e + ramp) H / v.
  // (Before 2026-12-02 the ramp was counted as t_ramp / 2, and runs ended ramp_strain short.) s.
  double time_at_strain(double e) const { return ramp_time() + (e * height - ramp_strain * height) / punch_velocity; }
};

}  // namespace pbx
