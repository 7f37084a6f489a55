#include "methods/common/build_space.h"

#include <optional>

namespace causticbench {

BuildSpaceMap build_space_map(const SceneObject& object, double frame) {
  const Transform transform = object.transform.at(frame);
  const glm::dvec3 rest_scale = object.transform.scale.at(0.0);
  glm::dmat3 scale(1.0);
  scale[0][0] = rest_scale.x;
  scale[1][1] = rest_scale.y;
  scale[2][2] = rest_scale.z;
  const glm::dmat3 linear = scale * glm::dmat3(transform.inverse);
  BuildSpaceMap map;
  map.linear = glm::mat3(linear);
  map.offset = Vec3(scale * glm::dvec3(transform.inverse[3]));
  map.normals = glm::mat3(glm::transpose(glm::inverse(linear)));
  return map;
}

Scene build_space_scene(const Scene& scene, int object) {
  Scene alone;
  alone.source = scene.source;
  alone.name = scene.name + " / " + scene.objects[object].name + " alone";
  alone.camera = scene.camera;
  alone.frames = 1;
  SceneObject copy = scene.objects[object];
  copy.transform = AnimatedTransform{};
  copy.transform.scale = Vec3Track::constant(scene.objects[object].transform.scale.at(0.0));
  alone.objects.push_back(std::move(copy));
  return alone;
}

ObjectLight object_light(const BuildSpaceMap& map, const LightFrame& light, const Vec3& build_center) {
  ObjectLight result;
  if (light.kind == LightKind::point) {
    const Vec3 to_light = map.point(light.position) - build_center;
    if (!(glm::length(to_light) > 0.0f)) return result;  // a light at the centre has no direction
    const Vec3 world_offset = glm::inverse(map.linear) * to_light;  // the distance is the world's
    result.direction = glm::normalize(to_light);
    result.irradiance = light.light->intensity / std::max(1e-12f, glm::dot(world_offset, world_offset));
  } else {
    result.direction = glm::normalize(map.vector(light.direction_to_light));
    result.irradiance = light.light->irradiance;
  }
  result.valid = true;
  return result;
}

std::vector<std::vector<Vec3>> object_light_directions(const Scene& scene, int object, const Vec3& build_center,
                                                       const std::vector<int>& frames) {
  std::vector<std::vector<Vec3>> directions(scene.lights.size());
  for (int frame : frames) {
    const BuildSpaceMap map = build_space_map(scene.objects[object], frame);
    for (size_t l = 0; l < scene.lights.size(); ++l) {
      const ObjectLight light = object_light(map, pose_light(scene.lights[l], frame), build_center);
      if (light.valid) directions[l].push_back(light.direction);
    }
  }
  return directions;
}

std::optional<std::vector<Vec3>> fixed_light_directions(const std::vector<std::vector<Vec3>>& directions) {
  auto same = [](const Vec3& a, const Vec3& b) { return glm::length(a - b) <= 1e-6f; };
  std::vector<Vec3> distinct;
  for (const auto& light : directions) {
    for (const Vec3& direction : light) {
      if (!same(direction, light.front())) return std::nullopt;
    }
    if (light.empty()) continue;
    bool known = false;
    for (const Vec3& seen : distinct) known = known || same(seen, light.front());
    if (!known) distinct.push_back(light.front());
  }
  if (distinct.empty()) return std::nullopt;
  return distinct;
}

}  // namespace causticbench
