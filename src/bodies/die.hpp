#pragma once
// The die of the paper (Fig. 1a): the specimen in [0, width] x [0, height] between three fixed
// walls and a punch moving down at punch_velocity; walls and punch are rigid bodies (indices into
// Scene::bodies). The die owns the punch timing, so the scene (end time, the punch's ramp) and the
// study's phase moduli (study/run_phases.cpp, the loading time) read one formula.

namespace pbx {

// die.ramp_strain when a deck does not give it
inline constexpr double kDefaultRampStrain = 0.002;

struct Die {
  double width = 0, height = 0;  // m (initial specimen box)
  double punch_velocity = 0;     // m/s, magnitude (the punch moves in -y)
  double ramp_strain = 0;        // strain over which the punch speed ramps up smoothly
  int left = -1, right = -1, bottom = -1, punch = -1;

  // The punch's speed rises as (1 - cos) over the ramp time, moving ramp_strain x height meanwhile
  // (at half its final speed on average), then stays at punch_velocity. s.
  double ramp_time() const { return punch_velocity > 0 ? 2.0 * ramp_strain * height / punch_velocity : 0.0; }
  // When the nominal strain e >= ramp_strain is reached: t_ramp + (e - ramp) H / v, i.e. (e + ramp) H / v.
  // (Before 2026-12-02 the ramp was counted as t_ramp / 2, and runs ended ramp_strain short.) s.
  double time_at_strain(double e) const { return ramp_time() + (e * height - ramp_strain * height) / punch_velocity; }
};

}  // namespace pbx
