// Affine transforms (translate, rotate, scale) and their animation by frame index.
#pragma once

#include <vector>

#include <glm/mat3x3.hpp>
#include <glm/mat4x4.hpp>

#include "core/config.h"
#include "core/math.h"

namespace causticbench {

struct Transform {
  glm::dmat4 matrix{1.0};
  glm::dmat4 inverse{1.0};

  static Transform from_parts(const glm::dvec3& translate, const glm::dvec3& rotate_degrees, const glm::dvec3& scale);
  Vec3 point(const Vec3& p) const;
  Vec3 vector(const Vec3& v) const;
  // Normals transform with the inverse transpose; the result is unit length.
  Vec3 normal(const Vec3& n) const;
  Vec3 inverse_point(const Vec3& p) const;
  Vec3 inverse_vector(const Vec3& v) const;
  // Largest factor by which the transform stretches a length (for bounding spheres).
  double max_scale() const;
};

// A value that may change with the frame index: a constant, or keyframes interpolated linearly and
// held constant before the first and after the last.
struct Vec3Track {
  std::vector<std::pair<double, glm::dvec3>> keys;  // (frame, value), sorted by frame

  static Vec3Track constant(const glm::dvec3& value) { return Vec3Track{{{0.0, value}}}; }
  glm::dvec3 at(double frame) const;
  bool animated() const { return keys.size() > 1; }
};

// translate / rotate (Euler degrees, applied X, then Y, then Z) / scale, each possibly animated.
struct AnimatedTransform {
  Vec3Track translate = Vec3Track::constant(glm::dvec3(0.0));
  Vec3Track rotate = Vec3Track::constant(glm::dvec3(0.0));
  Vec3Track scale = Vec3Track::constant(glm::dvec3(1.0));

  Transform at(double frame) const;
  bool animated() const { return translate.animated() || rotate.animated() || scale.animated(); }
};

// Reads `transform: {translate, rotate, scale}` and `animation: {keyframes: [{frame, translate, rotate,
// scale}, ...]}` from an object's map.
AnimatedTransform read_animated_transform(const ConfigNode& object);

// Rejects unknown keys in `animation.keyframes[*]` and `animation` of an owner whose animated
// tracks were read with read_vec3_track.
void finish_animation(const ConfigNode& owner);

// Reads a vec3 key that may be animated through `animation.keyframes[*].<key>`.
Vec3Track read_vec3_track(const ConfigNode& owner, const std::string& key, const glm::dvec3* fallback);

}  // namespace causticbench
