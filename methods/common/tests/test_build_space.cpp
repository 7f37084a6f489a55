// An object's build space (methods/common/build_space.h), which lpi, csl and prt precompute in: the
// direction towards each light and the irradiance it brings, worked out here by hand from the scene's
// numbers (the inverse rotation and offset applied on paper), and the "model only what the scene
// requires" rule that keeps one light direction for a static light.
#include <cmath>
#include <string>

#include <gtest/gtest.h>

#include "core/scene.h"
#include "methods/common/build_space.h"
#include "tests/test_support.h"

namespace causticbench {
namespace {

using causticbench::testing::scene_from_yaml;

// A glass ball at (2, 0, 0), turned 90 degrees about +y and scaled by 2; a sun and a point light.
const char* const kTurnedBall = R"(
camera: {position: [0, 3, 6], look_at: [2, 0, 0], resolution: [8, 8]}
lights:
  - {type: directional, direction: [-1, 0, 0], irradiance: 3}
  - {type: point, position: [2, 3, 0], intensity: 18}
  - {type: point, position: [2, 0, 0], intensity: 1}
objects:
  - shape: {type: sphere, radius: 0.5}
    material: {type: glass, ior: 1.5}
    transform: {translate: [2, 0, 0], rotate: [0, 90, 0], scale: 2}
)";

void expect_direction(const Vec3& got, const Vec3& expected) {
  EXPECT_NEAR(got.x, expected.x, 1e-6f);
  EXPECT_NEAR(got.y, expected.y, 1e-6f);
  EXPECT_NEAR(got.z, expected.z, 1e-6f);
}

TEST(BuildSpace, ObjectLightIsTheLightTurnedIntoTheObjectsFrame) {
  const Scene scene = scene_from_yaml(kTurnedBall);
  const BuildSpaceMap map = build_space_map(scene.objects[0], 0.0);
  const Vec3 centre = map.point(Vec3(2.0f, 0.0f, 0.0f));
  expect_direction(centre, Vec3(0.0f));  // the object's centre is build space's origin

  // The sun travels along -x: towards it is +x in the world. The ball is turned by Ry(90), which takes
  // +z to +x (Ry(a) (0, 0, 1) = (sin a, 0, cos a)), so in its own frame the sun lies along +z, at the
  // sun's irradiance.
  const ObjectLight sun = object_light(map, pose_light(scene.lights[0], 0.0), centre);
  ASSERT_TRUE(sun.valid);
  expect_direction(sun.direction, Vec3(0.0f, 0.0f, 1.0f));
  EXPECT_FLOAT_EQ(sun.irradiance.r, 3.0f);

  // The point light 3 above the centre: straight up in the object's frame (a turn about y keeps y),
  // at the world's distance, 3, not the scaled one: 18 / 3^2 = 2 W/m^2 at the centre.
  const ObjectLight bulb = object_light(map, pose_light(scene.lights[1], 0.0), centre);
  ASSERT_TRUE(bulb.valid);
  expect_direction(bulb.direction, Vec3(0.0f, 1.0f, 0.0f));
  EXPECT_NEAR(bulb.irradiance.r, 2.0f, 1e-5f);

  // A point light at the centre has no direction.
  EXPECT_FALSE(object_light(map, pose_light(scene.lights[2], 0.0), centre).valid);
}

// A scale that differs across axes turns a direction in build space (build space keeps the frame-0
// scale): a point light at world offset (1, 1, 0) from a ball scaled by (1, 2, 1) and turned by Rz(90)
// lies, in its frame, at Rz(-90) (1, 1, 0) = (1, -1, 0), before the scale (build space is scaled as at
// frame 0, so S0 S^-1 = 1); irradiance at the world distance, sqrt(2).
TEST(BuildSpace, ANonUniformScaleKeepsTheWorldsDistance) {
  const Scene scene = scene_from_yaml(R"(
camera: {position: [0, 3, 6], look_at: [0, 0, 0], resolution: [8, 8]}
lights: [{type: point, position: [1, 1, 0], intensity: 4}]
objects:
  - shape: {type: sphere, radius: 0.5}
    material: {type: mirror}
    transform: {rotate: [0, 0, 90], scale: [1, 2, 1]}
)");
  const BuildSpaceMap map = build_space_map(scene.objects[0], 0.0);
  const ObjectLight light = object_light(map, pose_light(scene.lights[0], 0.0), map.point(Vec3(0.0f)));
  ASSERT_TRUE(light.valid);
  expect_direction(light.direction, glm::normalize(Vec3(1.0f, -1.0f, 0.0f)));
  EXPECT_NEAR(light.irradiance.r, 2.0f, 1e-5f);
}

// Model only what the scene requires: a static light and object give one direction per light (and a
// light twice in the scene, one); an object that turns gives none fixed, so the method samples them all.
TEST(BuildSpace, AStaticLightHasOneDirectionAndATurningObjectNone) {
  const std::string lights =
      "lights: [{type: directional, direction: [0, -1, 0], irradiance: 1}, {type: directional, direction: [0, -1, 0], irradiance: 2}]\n";
  const std::string still = std::string(R"(
camera: {position: [0, 3, 6], look_at: [0, 0, 0], resolution: [8, 8]}
frames: 4
)") + lights + R"(objects:
  - shape: {type: sphere, radius: 0.5}
    material: {type: glass}
)";
  const Scene scene = scene_from_yaml(still);
  const auto fixed = fixed_light_directions(object_light_directions(scene, 0, Vec3(0.0f), {0, 1, 2, 3}));
  ASSERT_TRUE(fixed.has_value());
  ASSERT_EQ(fixed->size(), 1u);
  expect_direction(fixed->front(), Vec3(0.0f, 1.0f, 0.0f));

  const Scene turning = scene_from_yaml(still + R"(    animation:
      keyframes:
        - {frame: 0, rotate: [0, 0, 0]}
        - {frame: 3, rotate: [0, 0, 30]}
)");
  const auto directions = object_light_directions(turning, 0, Vec3(0.0f), {0, 1, 2, 3});
  ASSERT_EQ(directions.size(), 2u);
  ASSERT_EQ(directions[0].size(), 4u);
  // Frame 3: the ball turned by Rz(30) sees the light at Rz(-30) (0, 1, 0) = (sin 30, cos 30, 0).
  expect_direction(directions[0][3], Vec3(0.5f, std::sqrt(3.0f) / 2.0f, 0.0f));
  EXPECT_FALSE(fixed_light_directions(directions).has_value());
}

}  // namespace
}  // namespace causticbench
