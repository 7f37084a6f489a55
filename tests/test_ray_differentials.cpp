// Ray differentials through the shared photon tracer (core/ray_differential.h, CausticPhotonTracer::
// trace_emitted). A parallel beam reflected by a flat mirror stays parallel: every photon's footprint
// equals its emission texel, divided by the cosine at the receiver. Through a glass sphere (refraction,
// curvature), off a mirror ring's wall and through a smooth-mesh torus, the differentials agree with
// finite differences of neighbouring photons traced through the same choices.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

#include <gtest/gtest.h>

#include "core/photon_tracer.h"
#include "core/tracer.h"
#include "tests/test_support.h"

namespace causticbench {
namespace {

using causticbench::testing::scene_from_yaml;

struct Landing {
  bool found = false;
  Vec3 position{0.0f};
  int object = -1;
  RayDifferential differential;
};

// Photon `index` emitted downwards from (x, 3, z) with a unit beam texel spanned by +x and +z.
Landing land(const CausticPhotonTracer& photons, uint64_t index, float x, float z, Vec3 direction = Vec3(0, -1, 0)) {
  Ray ray;
  ray.origin = Vec3(x, 3.0f, z);
  ray.direction = glm::normalize(direction);
  ray.t_min = 0.0f;
  ray.t_max = 1e30f;
  RayDifferential differential;
  differential.dp_du = Vec3(1, 0, 0);
  differential.dp_dv = Vec3(0, 0, 1);
  Landing landing;
  PhotonStats stats;
  photons.trace_emitted(index, ray, Color(1.0f), differential, stats,
                        [&](const SurfaceHit& hit, const Vec3&, const Vec3&, const Color&, const RayDifferential& at) {
                          if (landing.found) return;
                          landing = Landing{true, hit.position, hit.object, at};
                        });
  return landing;
}

// A mirror turned 60 degrees about z sends the vertical beam down at 60 degrees from the vertical onto the
// floor: the footprint of a texel du x dv is du dv / cos 60, exactly, for every photon.
TEST(RayDifferentials, AFlatMirrorKeepsTheTexelsFootprint) {
  const Scene scene = scene_from_yaml(R"(
camera: {position: [0, 4, 4], look_at: [0, 0, 0], fov_degrees: 40, resolution: [8, 8]}
lights: [{type: directional, direction: [0, -1, 0], irradiance: 1}]
objects:
  - shape: {type: quad, size: [40, 40]}
    material: {type: diffuse, albedo: 0.5}
  - shape: {type: quad, size: [1, 1]}
    material: {type: mirror}
    transform: {translate: [0, 1, 0], rotate: [0, 0, 60]}
)");
  const SceneFrame frame(scene, 0.0);
  const Tracer tracer(frame);
  const CausticPhotonTracer photons(tracer, PhotonTracerSettings{});
  const double expected = 1.0 / std::cos(60.0 * kPiDouble / 180.0);
  int landed = 0;
  for (int i = 0; i < 50; ++i) {
    const float x = -0.2f + 0.4f * static_cast<float>(i % 7) / 6.0f, z = -0.4f + 0.8f * static_cast<float>(i / 7) / 7.0f;
    const Landing landing = land(photons, static_cast<uint64_t>(i), x, z);
    if (!landing.found) continue;
    ++landed;
    EXPECT_EQ(landing.object, 0);
    EXPECT_NEAR(footprint_area(landing.differential, 1.0f, 1.0f), expected, 1e-5 * expected) << i;
    EXPECT_LT(glm::length(landing.differential.dd_du) + glm::length(landing.differential.dd_dv), 1e-6f) << i;
  }
  EXPECT_EQ(landed, 50);
}

// Neighbours h apart traced with the same index take the same Fresnel choices (the same draws), except
// where a draw falls between their reflectances; pairs that land on different objects or far apart are
// left out. The differential against the finite difference, relative to its length: the median (bound
// 5e-3) and the 90th percentile (3e-2; 6e-2 on a mesh, whose interpolated normals change their derivative
// from one triangle to the next, within the step h) over the photons that land (measured: medians 7e-4 to
// 4e-3, 90th percentiles 2e-3 to 3.3e-2).
// Photons from a 20 x 20 grid of origins over [cx - sx, cx + sx] x [cz - sz, cz + sz] at height 3.
void expect_differentials_match_neighbours(const std::string& scene_text, Vec3 direction, float cx, float cz, float sx,
                                           float sz, const char* what, double high_bound = 3e-2) {
  const Scene scene = scene_from_yaml(scene_text);
  const SceneFrame frame(scene, 0.0);
  const Tracer tracer(frame);
  const CausticPhotonTracer photons(tracer, PhotonTracerSettings{3});
  const float h = 1e-3f;
  std::vector<double> errors;
  for (int i = 0; i < 400; ++i) {
    const float x = cx + sx * (static_cast<float>(i % 20) / 19.5f * 2.0f - 1.0f);
    const float z = cz + sz * (static_cast<float>(i / 20) / 19.5f * 2.0f - 1.0f) + 0.013f;
    const Landing centre = land(photons, static_cast<uint64_t>(i), x, z, direction);
    const Landing along_u = land(photons, static_cast<uint64_t>(i), x + h, z, direction);
    const Landing along_v = land(photons, static_cast<uint64_t>(i), x, z + h, direction);
    if (!centre.found || !along_u.found || !along_v.found || along_u.object != centre.object ||
        along_v.object != centre.object)
      continue;
    const Vec3 finite_u = (along_u.position - centre.position) / h, finite_v = (along_v.position - centre.position) / h;
    if (glm::length(finite_u - centre.differential.dp_du) > 0.5f * glm::length(finite_u) + 1.0f) continue;  // another path
    errors.push_back(glm::length(finite_u - centre.differential.dp_du) / std::max(1e-3f, glm::length(finite_u)));
    errors.push_back(glm::length(finite_v - centre.differential.dp_dv) / std::max(1e-3f, glm::length(finite_v)));
  }
  ASSERT_GT(errors.size(), 250u) << what;
  std::sort(errors.begin(), errors.end());
  const double median = errors[errors.size() / 2], high = errors[errors.size() * 9 / 10];
  std::printf("%s: %zu differentials against finite differences: median relative error %.2e, 90th percentile %.2e\n",
              what, errors.size(), median, high);
  EXPECT_LT(median, 5e-3) << what;
  EXPECT_LT(high, high_bound) << what;
}

TEST(RayDifferentials, AGlassSphereAgreesWithNeighbouringPhotons) {
  expect_differentials_match_neighbours(R"(
camera: {position: [0, 4, 4], look_at: [0, 0, 0], fov_degrees: 40, resolution: [8, 8]}
lights: [{type: directional, direction: [0, -1, 0], irradiance: 1}]
objects:
  - shape: {type: quad, size: [40, 40]}
    material: {type: diffuse, albedo: 0.5}
  - shape: {type: sphere, radius: 0.4}
    material: {type: glass, ior: 1.5}
    transform: {translate: [0, 1.2, 0]}
)",
                                        Vec3(0, -1, 0), 0.0f, 0.0f, 0.38f, 0.38f, "glass sphere");
}

// The ring's inner wall (a mirror cylinder: curved one way) under a beam 27 degrees from the vertical,
// and a glass torus, a smooth mesh whose interpolated normals bend the rays.
TEST(RayDifferentials, AMirrorRingAndASmoothMeshAgreeWithNeighbouringPhotons) {
  expect_differentials_match_neighbours(R"(
camera: {position: [0, 4, 4], look_at: [0, 0, 0], fov_degrees: 40, resolution: [8, 8]}
lights: [{type: directional, direction: [0, -1, 0], irradiance: 1}]
objects:
  - shape: {type: quad, size: [40, 40]}
    material: {type: diffuse, albedo: 0.5}
  - shape: {type: ring, radius: 1.0, height: 0.5}
    material: {type: mirror}
)",
                                        Vec3(0, -1, 0.5f), 0.0f, -0.6f, 0.7f, 0.2f, "mirror ring");
  expect_differentials_match_neighbours(R"(
camera: {position: [0, 4, 4], look_at: [0, 0, 0], fov_degrees: 40, resolution: [8, 8]}
lights: [{type: directional, direction: [0, -1, 0], irradiance: 1}]
objects:
  - shape: {type: quad, size: [40, 40]}
    material: {type: diffuse, albedo: 0.5}
  - shape: {type: torus, major_radius: 0.5, minor_radius: 0.2, segments: [96, 48]}
    material: {type: glass, ior: 1.5}
    transform: {translate: [0, 1.2, 0]}
)",
                                        Vec3(0, -1, 0), 0.0f, 0.0f, 0.7f, 0.7f, "glass torus (smooth mesh)", 6e-2);
}

}  // namespace
}  // namespace causticbench
