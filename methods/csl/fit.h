// The spot light fit of a bundle (Liu et al. 2008, Section 3.1.2): with the optical axis on the
// bundle's axis, the light plane origin c = b + l a and the profile (kappa = 1 / alpha, beta) that
// minimise Eq. 5, the sum over the bundle's rays of (t1^2 + t2^2) |d - e|^2, where e is the direction
// of the spot light's ray from the point p where the bundle ray meets the light plane, t1 = |p - q|
// and t2 = t1 + w, w four times the object's bounding box size. Solved with Ceres (the paper used
// Brent's method), from a linear first guess: 1 / f against r is the line kappa + kappa beta r.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "methods/csl/bundles.h"
#include "methods/csl/spot_light.h"

namespace causticbench::csl {

struct FitSettings {
  double reach = 1.0;          // w of Eq. 5, scene units
  int max_rays = 4096;         // rays of the bundle the objective sums over (evenly strided)
  int max_iterations = 100;    // Ceres iterations
  double plane_range = 1.0;    // l may lie this far behind the ray origins (scene units; see fit.cpp)
};

struct Fit {
  glm::dvec3 origin{0.0};  // c
  Profile profile;
  double ell = 0.0;        // l: c = b + l a
  double initial_cost = 0.0, final_cost = 0.0;  // Eq. 5 over the rays used, at the first guess and at the end
  int iterations = 0;
  int rays_used = 0;
  bool converged = false;
  // Ceres found no usable solution (a residual or Jacobian that is not finite): the first guess is kept.
  // Stored in the build files with the rest (a plain value: build format 2).
  bool failed = false;
};

// The geometry of one bundle ray against a candidate light plane: p, r and the chord |d - e|.
struct RayOnPlane {
  glm::dvec3 p{0.0};
  double r = 0.0;
  double t1 = 0.0;        // |p - q|
  double chord = 0.0;     // |d - e|: about the angle between the bundle ray and the spot light's ray
  bool valid = false;     // false when the ray is parallel to the plane
};
RayOnPlane ray_on_plane(const CausticRay& ray, const BundleAxis& axis, double ell, const Profile& profile);

Fit fit_spot_light(const std::vector<CausticRay>& rays, const std::vector<uint32_t>& members, const BundleAxis& axis,
                   const FitSettings& settings);

}  // namespace causticbench::csl
