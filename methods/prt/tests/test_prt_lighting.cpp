// methods/prt/lighting.h: the frame's lighting of an object in its build space. An environment turned by
// rotating its world coefficients equals its directions turned before projecting them (an identity of
// band-limited functions: to rounding); a directional light is its truncated delta, a point light one
// from the object's centre with the irradiance there; a window keeps band 0.
#include <cmath>

#include <gtest/gtest.h>

#include "methods/prt/lighting.h"
#include "tests/test_support.h"

namespace causticbench::prt {
namespace {

using causticbench::testing::scene_from_yaml;

// A glass ball turned 30 degrees about y and 50 about x, scaled 2, under a Gaussian spot, a sun and a
// point light.
const char* const kTurnedBall = R"(
camera: {position: [0, 3, 3], look_at: [0, 0, 0], fov_degrees: 50, resolution: [8, 8]}
lights:
  - {type: environment, procedural: gaussian_spot, direction: [0.4, -1, 0], irradiance: 1.5, solid_angle_sr: 0.2}
  - {type: directional, direction: [0.2, -1, 0.3], irradiance: 2}
  - {type: point, position: [1, 3, 0], intensity: 9}
objects:
  - shape: {type: sphere, radius: 0.5}
    material: {type: glass, ior: 1.5}
    transform: {translate: [0.2, 0.5, 0], rotate: [50, 30, 0], scale: 2}
)";

TEST(PrtLighting, RotatedEnvironmentCoefficientsEqualTheTurnedProjection) {
  const Scene scene = scene_from_yaml(kTurnedBall);
  const SceneFrame frame(scene, 0.0);
  const BuildSpaceMap map = build_space_map(scene.objects[0], 0.0);
  glm::dmat3 rotation;
  ASSERT_TRUE(rigid_rotation(map.linear, rotation)) << "a uniform scale turns directions rigidly";
  const int bands = 6;
  LightingProjector projector(bands);
  const std::vector<LightFrame> spot = {frame.lights[0]};
  const FrameLighting turned = projector.project(spot, map, Vec3(0.0f), HarmonicWindow::none);
  EXPECT_GT(turned.quadrature_points, 0u);
  const std::vector<glm::dvec3> direct =
      harmonic_weights(bands, environment_quadrature(frame.lights[0], harmonic_quadrature_angle(bands)), map.linear);
  double largest = 0.0;
  for (size_t k = 0; k < direct.size(); ++k)
    for (int c = 0; c < 3; ++c) {
      EXPECT_NEAR(turned.coefficients[c][k], direct[k][c], 1e-6 * std::abs(direct[0][c])) << "k " << k << " c " << c;
      largest = std::max(largest, std::abs(direct[k][c]));
    }
  EXPECT_GT(largest, 0.0);
  // Band 0 is the map's total over sqrt(4 pi), whatever the turn (the spot's radiance integrates to a
  // little under its irradiance of 1.5: sin theta < theta).
  const double total = environment_quadrature(frame.lights[0], harmonic_quadrature_angle(bands)).total().y;
  EXPECT_NEAR(turned.coefficients[1][0] * std::sqrt(4.0 * kPiDouble), total, 1e-9 * total);
  EXPECT_NEAR(total, 1.5, 0.03);
  // The second frame's projection is cached: no quadrature point projected again.
  EXPECT_EQ(projector.project(spot, map, Vec3(0.0f), HarmonicWindow::none).quadrature_points, 0u);
}

TEST(PrtLighting, DirectionalAndPointLightsAreTruncatedDeltasFromTheCentre) {
  const Scene scene = scene_from_yaml(kTurnedBall);
  const SceneFrame frame(scene, 0.0);
  const BuildSpaceMap map = build_space_map(scene.objects[0], 0.0);
  const Vec3 centre = map.point(Vec3(0.2f, 0.5f, 0.0f));
  const int bands = 4;
  LightingProjector projector(bands);
  // The direction towards each light in build space, worked out by hand: the ball is turned by
  // R = Ry(30) Rx(50) (core/transform.cpp applies x first) and scaled uniformly, and build space keeps
  // only its scale, so a world direction d is R^-1 d = Rx(-50) Ry(-30) d there.
  auto turn_back = [](glm::dvec3 d) {
    const double y = -30.0 * kPiDouble / 180.0, x = -50.0 * kPiDouble / 180.0;
    d = glm::dvec3(std::cos(y) * d.x + std::sin(y) * d.z, d.y, -std::sin(y) * d.x + std::cos(y) * d.z);
    return glm::normalize(glm::dvec3(d.x, std::cos(x) * d.y - std::sin(x) * d.z, std::sin(x) * d.y + std::cos(x) * d.z));
  };
  const struct {
    size_t light;
    glm::dvec3 direction;  // towards the light, build space
    double irradiance;     // at the ball's centre
  } cases[] = {{1, turn_back(-glm::dvec3(0.2, -1.0, 0.3)), 2.0},
               {2, turn_back(glm::dvec3(1.0, 3.0, 0.0) - glm::dvec3(0.2, 0.5, 0.0)), 9.0 / (0.8 * 0.8 + 2.5 * 2.5)}};
  for (const auto& light : cases) {
    const FrameLighting lighting = projector.project({frame.lights[light.light]}, map, centre, HarmonicWindow::none);
    const std::vector<double> expected = directional_coefficients(bands, light.direction, light.irradiance);
    for (size_t k = 0; k < expected.size(); ++k)
      EXPECT_NEAR(lighting.coefficients[1][k], expected[k], 1e-5 * light.irradiance) << light.light << ": " << k;
  }
  // The point light's irradiance at the centre: 9 / |(1, 3, 0) - (0.2, 0.5, 0)|^2.
  EXPECT_NEAR(object_light(map, frame.lights[2], centre).irradiance.g, 9.0 / (0.8 * 0.8 + 2.5 * 2.5), 1e-4);
  // A window keeps band 0 (the total) and damps the rest.
  const FrameLighting plain = projector.project({frame.lights[1]}, map, centre, HarmonicWindow::none);
  const FrameLighting windowed = projector.project({frame.lights[1]}, map, centre, HarmonicWindow::hanning);
  EXPECT_DOUBLE_EQ(windowed.coefficients[0][0], plain.coefficients[0][0]);
  EXPECT_LT(std::abs(windowed.coefficients[0][4]), std::abs(plain.coefficients[0][4]) + 1e-15);
}

}  // namespace
}  // namespace causticbench::prt
