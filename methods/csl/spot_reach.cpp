#include "methods/csl/spot_reach.h"

#include <algorithm>
#include <cmath>

#include <glm/geometric.hpp>

namespace causticbench::csl {

SpotReach::SpotReach(const SpotGeometry& light, double support_radius)
    : origin_(light.origin),
      axis_(light.axis),
      kappa_(light.profile.kappa),
      beta_(light.profile.beta),
      // A root at radius r is looked up at |(x, y)| = r up to the float rounding of the plane's axes u
      // and v (about 1e-7 of r): a relative margin far above it.
      support_(support_radius * (1.0 + 1e-5)) {}

double SpotReach::reach(double z) const {
  // s(r) = A r - B r^2 with A = 1 - z kappa, B = z kappa beta: its largest |s| over [0, R] is at R or
  // at the vertex r = A / (2 B) where that lies inside.
  const double a = 1.0 - z * kappa_, b = z * kappa_ * beta_, outer = support_;
  double largest = std::fabs(a * outer - b * outer * outer);
  if (b != 0.0) {
    const double vertex = a / (2.0 * b);
    if (vertex > 0.0 && vertex < outer) largest = std::max(largest, std::fabs(a * vertex - b * vertex * vertex));
  }
  return largest;
}

bool SpotReach::may_reach(const glm::dvec3& center, double radius, double near_axis) const {
  const glm::dvec3 offset = center - origin_;
  // The evaluation's heights and distances carry rounding of a few ulps of the offset, and a root
  // near a double root (the caustic's fold) moves the distance it stands for by about 1e-16 of it:
  // margins far above both.
  const double slack = 1e-9 * (glm::length(offset) + radius);
  const double z = glm::dot(offset, axis_);
  if (z + radius + slack <= 0.0) return false;  // every point is behind the light plane
  const double nearest = glm::length(offset - z * axis_) - radius - slack;
  if (nearest < near_axis) return true;  // the on-axis treatments
  const double high = z + radius + slack, low = std::max(0.0, z - radius - slack);
  return nearest <= std::max(reach(low), reach(high)) * (1.0 + 1e-6) + slack;
}

}  // namespace causticbench::csl
