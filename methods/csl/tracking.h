// Matching the spot lights of two neighbouring light directions (Liu et al. 2008, Section 4.2): the
// light turns from s0 to s1 in small steps; at each step a grid of rays is traced and every spot
// light of s0 has its axis refined on those rays as bundle extraction refines an axis (steps 3 to 5 of
// Section 3.1.1); at s1 the moved axes are paired with s1's spot lights in order of increasing axis
// distance, each at most once and within a threshold. An unmatched spot light of s0 gets a black
// partner at s1 on its moved axis (the paper); an unmatched one of s1 gets a black partner at s0 on its
// own axis (the paper leaves this case open; a black partner keeps every spot light in exactly one
// pair of the edge, which the triples of Section 4.3 need).
#pragma once

#include <cstdint>
#include <vector>

#include "core/specular_tree.h"
#include "core/tracer.h"
#include "methods/csl/bundles.h"
#include "methods/csl/generate.h"

namespace causticbench::csl {

struct TrackingSettings {
  int steps = 20;                 // the paper's 20 steps from s0 to s1
  int rays_per_side = 128;        // rays of each step's grid
  SpecularTreeSettings tree;
  BundleSettings bundle;          // thresholds for assigning rays to an axis
  double match_distance = 1.0;    // scene units: pairs farther apart stay unmatched
};

// The axis distance of the paper, dist(A0, A1) = sqrt(|b0 - b1|^2 + B |a0 - a1|^2), with B the
// square of the bounding sphere's diameter (B must be an area for the sum to have one unit) and b the
// point of each axis nearest the object's centre: where along its axis a spot light's plane lies is
// the fit's choice (Eq. 5 is not convex in l), not the bundle's, and the paper's "position" of an axis
// must not depend on it. Coaxial spot lights (a lens makes one per ring of its aperture) are told apart
// by a third term, B (theta0 - theta1)^2, theta the angle at which the ray carrying the median of a
// spot light's flux converges on its axis (convergence_angle), which the plane's position does not change.
double axis_distance(const BundleAxis& first, double first_convergence, const BundleAxis& second,
                     double second_convergence, const BoundingSphere& bounds);

// The signed angle (radians; negative: diverging) between the axis and the ray that leaves the light
// plane at the radius holding half of the spot light's flux; 0 for a black image.
double convergence_angle(const SpotLight& light);

// One matched pair on an edge: the spot lights' indices in their sets, or ~k (negative) for the k-th
// black spot light this match made on that side.
struct LightPair {
  int32_t first = 0, second = 0;
};

struct EdgeMatch {
  std::vector<LightPair> pairs;
  std::vector<SpotLight> black_first, black_second;  // made for the first and the second set
  std::vector<double> distances;                      // per matched pair (not for black partners)
  int tracked_lost = 0;   // spot lights of the first set whose axis lost every ray on the way
  double seconds = 0.0;
};

// Tracks `first`'s spot lights from `first.direction` to `second.direction` through the object that
// `tracer` holds alone, and pairs them with `second`'s.
EdgeMatch match_neighbours(const Tracer& tracer, const BoundingSphere& bounds, const SpotLightSet& first,
                           const SpotLightSet& second, const TrackingSettings& settings);

// The axes of `set`'s spot lights moved from its direction to `to_light` in `settings.steps` steps. A
// moved axis keeps its light plane origin at the same signed distance along the axis from the point
// nearest the object's centre (the nearest point of each new axis to the old origin drifted by up to
// four bounding radii over 20 steps on the bunny).
std::vector<BundleAxis> track_axes(const Tracer& tracer, const BoundingSphere& bounds, const SpotLightSet& set,
                                   const Vec3& to_light, const TrackingSettings& settings, int& lost);

// A spot light with `like`'s profile on the given axis and an all-black image of `like`'s size.
SpotLight black_spot_light(const SpotLight& like, const BundleAxis& axis);

}  // namespace causticbench::csl
