// The receivers a caustic spot light can light (the CPU backend's cull, render knob `cull`): the
// volume its rays sweep, the frustum of its light plane's image. A ray leaving the plane at radius r
// is at the signed radius s(r, z) = r (1 - z kappa (1 + beta r)) at height z (spot_light.h), so the
// rays from radii [0, R] reach, at height z, the points within
//   reach(z) = max over r in [0, R] of |s(r, z)|
// of the axis (s is continuous and s(0, z) = 0, so every distance below it is met by some ray, and
// none above it). R is the image's support radius, beyond which every lookup reads zero texels.
// For a fixed r, |s(r, z)| is the absolute value of a linear function of z, so convex; reach is their
// maximum, so convex too, and over an interval of heights it is at most its larger end value. That
// bounds a whole sphere of receiver points with two evaluations, exactly and conservatively.
#pragma once

#include <glm/vec3.hpp>

#include "methods/csl/spot_light.h"

namespace causticbench::csl {

class SpotReach {
 public:
  SpotReach() = default;
  // `support_radius`: the light plane radius beyond which the image is zero (the Image concept's
  // support_radius(), spot_light.h).
  SpotReach(const SpotGeometry& light, double support_radius);

  // The largest distance from the axis at which a ray from radii [0, support] is at height z.
  double reach(double z) const;
  // Whether a point within `radius` of `center` (build space) may receive a non-zero contribution:
  // false only where evaluate_spot_light is zero for every such point. `near_axis`: the largest
  // distance from the axis at which the evaluation treats a point specially (the footprint radius
  // for on_axis: integrate, axis_epsilon for epsilon); such points are always kept.
  bool may_reach(const glm::dvec3& center, double radius, double near_axis) const;

 private:
  glm::dvec3 origin_{0.0}, axis_{0.0, 0.0, 1.0};
  double kappa_ = 0.0, beta_ = 0.0, support_ = 0.0;
};

}  // namespace causticbench::csl
