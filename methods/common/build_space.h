// An object's build space, shared by the methods that precompute per specular object (lpi, csl): the
// object scaled as at frame 0, neither rotated nor translated. A frame's world point p maps to it by
// S0 T_f^-1 p (T_f: the object's transform at that frame, S0: its scale at frame 0), so a caustic
// precomputed there moves and turns with the object and one build serves any placement of it.
#pragma once

#include <optional>
#include <vector>

#include <glm/mat3x3.hpp>

#include "core/scene.h"

namespace causticbench {

// A frame's map from world space into an object's build space.
struct BuildSpaceMap {
  glm::mat3 linear{1.0f};   // S0 M_f^-1
  Vec3 offset{0.0f};
  glm::mat3 normals{1.0f};  // inverse transpose of `linear`, for normals (normalise after)
  Vec3 point(const Vec3& p) const { return linear * p + offset; }
  Vec3 vector(const Vec3& v) const { return linear * v; }
};
BuildSpaceMap build_space_map(const SceneObject& object, double frame);

// The object alone, posed in build space (a scene of one object, for tracing through it).
Scene build_space_scene(const Scene& scene, int object);

// One light as an object sees it in one frame: the unit direction towards it in build space, and the
// irradiance it brings. A point light is taken as a directional light from the object's centre with
// the irradiance there (the assumption of Wyman 2003 and Liu 2008). `valid` is false for a point
// light at the centre, which has no direction.
struct ObjectLight {
  Vec3 direction{0.0f, 1.0f, 0.0f};
  Color irradiance{0.0f};
  bool valid = false;
};
ObjectLight object_light(const BuildSpaceMap& map, const LightFrame& light, const Vec3& build_center);

// Per scene light, the directions of object_light over `frames` (invalid ones left out).
std::vector<std::vector<Vec3>> object_light_directions(const Scene& scene, int object, const Vec3& build_center,
                                                       const std::vector<int>& frames);

// Model only what the scene requires: the distinct directions towards the lights when none of them
// changes over the frames (each light's direction within 1e-6 of its first), otherwise nothing.
std::optional<std::vector<Vec3>> fixed_light_directions(const std::vector<std::vector<Vec3>>& directions);

}  // namespace causticbench
