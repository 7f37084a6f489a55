// Caustic object rays (Liu et al. 2008, Section 3.1): a regular grid of rays_per_side x rays_per_side
// parallel rays in the light's direction over the square that covers the object's bounding sphere
// (the rays that miss the object are its silhouette's outside and carry nothing), each traced through
// the object alone by the splitting tracer (core/specular_tree.h) until every branch leaves it. What
// leaves is the light field the spot lights approximate.
#pragma once

#include <vector>

#include "core/specular_tree.h"

namespace causticbench::csl {

struct CausticRay {
  Vec3 origin;     // where it left the object
  Vec3 direction;  // unit
  Color energy;    // W per W/m^2 of the light's irradiance: the area of its grid cell times what is left
  float weight;    // luminance(energy), the scalar the clustering weighs by
};

struct ObjectRays {
  std::vector<CausticRay> rays;
  double spacing = 0.0;          // distance between neighbouring grid rays
  double entering = 0.0;         // luminance flux that entered the object (per unit irradiance)
  SpecularTreeStats stats;
  double seconds = 0.0;
};

// `tracer` over the object alone (build space); `to_light`: unit direction towards the light.
ObjectRays trace_object_rays(const Tracer& tracer, const BoundingSphere& bounds, const Vec3& to_light, int rays_per_side,
                             const SpecularTreeSettings& settings);

}  // namespace causticbench::csl
