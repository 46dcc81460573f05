#pragma once
// Automatic choice of the linear (elastic) part of a stress-strain curve.
#include <string>
#include <vector>

namespace pbx {

struct LinearWindowOptions {
  double start = 0;          // first strain of the window (the end of the punch ramp)
  double tolerance = 0.10;   // allowed drop of the end tangent below the window's slope
  int min_points = 8;        // the window never has fewer points
  double min_span = 0;       // ... nor spans less strain (rows of any density give one window)
  double max_strain = 0.02;  // the window never extends beyond this strain
};

struct LinearWindow {
  double lo = 0, hi = 0;  // strain
  int points = 0;
  bool automatic = true;
  std::string note;
};

// Grows the window [start, e_j] point by point from min_points on. At each end point j a line is
// fitted over the whole window (slope S_j) and another over its last max(5, 1/3) points (the end
// tangent T_j). The window ends at the last j that passed when two consecutive j have
// T_j < (1 - tolerance) S_j: a softening curve flattens at its end first, while noise in T_j is
// averaged over several points and a single low tangent is not enough. The points past the knee
// that this test lets in are then trimmed: the window ends before the first point of its last
// third lying below the line through its first two thirds by more than max(4 rms, 0.2 %).
// Throws InputError if fewer than min_points points lie in [start, max_strain].
LinearWindow find_linear_window(const std::vector<double>& strain, const std::vector<double>& stress,
                                const LinearWindowOptions& opt);

}  // namespace pbx
