#pragma once
// Exact area of (union of circles) ∩ (box [0,W] x [0,H]) by Green's theorem: the boundary of that
// set consists of circle arcs that no other circle covers and that lie in the box, plus stretches
// of the box edges that some circle covers; area = 1/2 ∮ (x dy - y dx) over them. Used for the
// binder mass balance, where binder coats may overlap each other and be cut by the box edges.
#include <vector>

#include <Eigen/Dense>

namespace pbx {

struct Circle {
  Eigen::Vector2d c;
  double r;
};

double union_area_in_box(const std::vector<Circle>& circles, const Eigen::Vector2d& box);

}  // namespace pbx
