#include "core/transform.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include <fmt/format.h>

#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/matrix_inverse.hpp>

namespace causticbench {

Transform Transform::from_parts(const glm::dvec3& translate, const glm::dvec3& rotate_degrees,
                                const glm::dvec3& scale) {
  glm::dmat4 m(1.0);
  m = glm::translate(m, translate);
  m = glm::rotate(m, glm::radians(rotate_degrees.z), glm::dvec3(0, 0, 1));
  m = glm::rotate(m, glm::radians(rotate_degrees.y), glm::dvec3(0, 1, 0));
  m = glm::rotate(m, glm::radians(rotate_degrees.x), glm::dvec3(1, 0, 0));
  m = glm::scale(m, scale);
  return Transform{m, glm::inverse(m)};
}

Vec3 Transform::point(const Vec3& p) const { return Vec3(matrix * glm::dvec4(glm::dvec3(p), 1.0)); }
Vec3 Transform::vector(const Vec3& v) const { return Vec3(matrix * glm::dvec4(glm::dvec3(v), 0.0)); }
Vec3 Transform::normal(const Vec3& n) const {
  glm::dvec3 transformed = glm::transpose(glm::dmat3(inverse)) * glm::dvec3(n);
  return Vec3(glm::normalize(transformed));
}
Vec3 Transform::inverse_point(const Vec3& p) const { return Vec3(inverse * glm::dvec4(glm::dvec3(p), 1.0)); }
Vec3 Transform::inverse_vector(const Vec3& v) const { return Vec3(inverse * glm::dvec4(glm::dvec3(v), 0.0)); }

double Transform::max_scale() const {
  glm::dmat3 linear(matrix);
  return std::max({glm::length(linear[0]), glm::length(linear[1]), glm::length(linear[2])});
}

glm::dvec3 Vec3Track::at(double frame) const {
  if (keys.size() == 1 || frame <= keys.front().first) return keys.front().second;
  if (frame >= keys.back().first) return keys.back().second;
  for (size_t i = 1; i < keys.size(); ++i) {
    if (frame <= keys[i].first) {
      double t = (frame - keys[i - 1].first) / (keys[i].first - keys[i - 1].first);
      return glm::mix(keys[i - 1].second, keys[i].second, t);
    }
  }
  return keys.back().second;
}

namespace {

glm::dvec3 read_scale(const ConfigNode& node) {
  ConfigNode value = node.child("scale");
  if (value.is_scalar()) {
    double s = value.as_number();
    if (s <= 0.0) value.fail_here("a positive scale", value.describe_value());
    return glm::dvec3(s);
  }
  glm::dvec3 s = node.vec3("scale");
  if (s.x <= 0.0 || s.y <= 0.0 || s.z <= 0.0) value.fail_here("three positive scale factors", value.describe_value());
  return s;
}

// A point's coordinates must stay where single-precision geometry (Embree, the tracer's rays) still
// resolves the scene: beyond kMaximumCoordinate a float's spacing reaches 0.06 and rays assert or miss.
glm::dvec3 checked_point(const ConfigNode& node, const std::string& key, const glm::dvec3& value) {
  static const std::vector<std::string> points = {"translate", "position", "look_at"};
  if (std::find(points.begin(), points.end(), key) == points.end()) return value;
  for (int i = 0; i < 3; ++i) {
    if (!(std::abs(value[i]) <= kMaximumCoordinate)) {
      node.fail(key, fmt::format("coordinates within +-{:g} (rays are traced in single precision, which stops "
                                 "resolving the scene beyond that)", kMaximumCoordinate),
                fmt::format("[{}, {}, {}]", value.x, value.y, value.z));
    }
  }
  return value;
}

glm::dvec3 read_component(const ConfigNode& node, const std::string& key, const glm::dvec3& fallback) {
  if (!node.has(key)) return fallback;
  return key == "scale" ? read_scale(node) : checked_point(node, key, node.vec3(key));
}

}  // namespace

namespace {

// The keyframes of `key` under owner.animation.keyframes, sorted by frame; empty when none animate it.
std::vector<std::pair<double, glm::dvec3>> read_keyframes(const ConfigNode& owner, const std::string& key) {
  std::vector<std::pair<double, glm::dvec3>> animated;
  std::optional<ConfigNode> animation = owner.optional_child("animation");
  if (!animation) return animated;
  ConfigNode keyframes = animation->child("keyframes");
  if (keyframes.size() < 2) keyframes.fail_here("at least two keyframes", keyframes.describe_value());
  for (size_t i = 0; i < keyframes.size(); ++i) {
    ConfigNode keyframe = keyframes.at(i);
    if (!keyframe.has(key)) continue;
    double frame = keyframe.number("frame", 0.0, 1e9);
    animated.push_back({frame, read_component(keyframe, key, glm::dvec3(0.0))});
  }
  std::stable_sort(animated.begin(), animated.end(), [](auto& a, auto& b) { return a.first < b.first; });
  for (size_t i = 1; i < animated.size(); ++i) {
    if (animated[i].first == animated[i - 1].first) {
      keyframes.fail_here("keyframes with distinct frame numbers for '" + key + "'",
                          "frame " + std::to_string(animated[i].first) + " twice");
    }
  }
  return animated;
}

// A track whose still value is `static_owner[key]` (or the fallback) and whose keyframes, if any,
// come from animated_owner.animation.keyframes[*][key].
Vec3Track read_track(const std::optional<ConfigNode>& static_owner, const ConfigNode& animated_owner,
                     const std::string& key, const glm::dvec3* fallback) {
  std::vector<std::pair<double, glm::dvec3>> animated = read_keyframes(animated_owner, key);
  // The still value is validated even when keyframes replace it, so that a typo there is reported.
  glm::dvec3 still = fallback ? *fallback : glm::dvec3(0.0);
  if (static_owner && (static_owner->has(key) || (fallback == nullptr && animated.empty()))) {
    still = key == "scale" ? read_scale(*static_owner) : checked_point(*static_owner, key, static_owner->vec3(key));
  }
  return animated.empty() ? Vec3Track::constant(still) : Vec3Track{animated};
}

}  // namespace

Vec3Track read_vec3_track(const ConfigNode& owner, const std::string& key, const glm::dvec3* fallback) {
  return read_track(owner, owner, key, fallback);
}

void finish_animation(const ConfigNode& owner) {
  std::optional<ConfigNode> animation = owner.optional_child("animation");
  if (!animation) return;
  ConfigNode keyframes = animation->child("keyframes");
  for (size_t i = 0; i < keyframes.size(); ++i) {
    ConfigNode keyframe = keyframes.at(i);
    // Asking for 'frame' makes it a known key, so that a keyframe holding only values this owner
    // cannot animate fails on those values, with the animatable keys listed.
    keyframe.has("frame");
    if (keyframe.keys().size() < 2) keyframe.fail_here("a frame and at least one animated value", keyframe.describe_value());
    keyframe.finish();
  }
  animation->finish();
}

AnimatedTransform read_animated_transform(const ConfigNode& object) {
  AnimatedTransform result;
  std::optional<ConfigNode> transform = object.optional_child("transform");
  const glm::dvec3 zero(0.0), one(1.0);
  result.translate = read_track(transform, object, "translate", &zero);
  result.rotate = read_track(transform, object, "rotate", &zero);
  result.scale = read_track(transform, object, "scale", &one);
  if (transform) transform->finish();
  finish_animation(object);
  return result;
}

Transform AnimatedTransform::at(double frame) const {
  return Transform::from_parts(translate.at(frame), rotate.at(frame), scale.at(frame));
}

}  // namespace causticbench
