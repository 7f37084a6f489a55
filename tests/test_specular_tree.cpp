// The deterministic ray trees of core/specular_tree.h (csl's caustic object rays): energy is conserved
// branch by branch (started = missed + exited + dropped + absorbed, the balance csl's lost flux rests
// on; a starting ray that meets nothing is missed, which csl leaves out of what enters), and the
// branches through a ball and off a mirror carry the closed-form Fresnel and Beer-Lambert weights.
// Links only causticbench_core.
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "core/scene.h"
#include "core/scene_description.h"
#include "core/specular_tree.h"
#include "core/tracer.h"

namespace causticbench {
namespace {

Scene ball_scene(const std::string& material, bool floor) {
  std::string yaml = R"(
camera: {position: [0, 3, 3], look_at: [0, 0, 0], resolution: [8, 8]}
lights: [{type: directional, direction: [0, -1, 0], irradiance: 1}]
objects:
  - shape: {type: sphere, radius: 0.5}
    material: )" + material + "\n";
  if (floor) {
    yaml += R"(  - shape: {type: quad, size: [8, 8]}
    material: {type: diffuse, albedo: 0.5}
    transform: {translate: [0, -1, 0]}
)";
  }
  return load_scene_from_string(yaml, "test.yaml", ".");
}

struct Traced {
  SpecularTreeStats stats;
  std::vector<ExitRay> exits;
};

// Rays straight down onto the ball at offsets x across it (z = 0), from above it.
Traced trace_down(const Scene& scene, const std::vector<float>& offsets, const SpecularTreeSettings& settings) {
  SceneFrame frame(scene, 0);
  Tracer tracer(frame);
  Traced traced;
  for (float x : offsets) {
    Ray ray;
    ray.origin = Vec3(x, 2.0f, 0.0f);
    ray.direction = Vec3(0.0f, -1.0f, 0.0f);
    trace_specular_tree(tracer, ray, Color(1.0f), settings, traced.stats,
                        [&](const ExitRay& exit) { traced.exits.push_back(exit); });
  }
  return traced;
}

// Unpolarised Fresnel reflectance at normal incidence, ((n - 1) / (n + 1))^2, written apart from
// core/optics.cpp.
double normal_reflectance(double ior) { return std::pow((ior - 1.0) / (ior + 1.0), 2.0); }

std::vector<float> offsets_across() {
  std::vector<float> offsets;
  for (int i = 0; i < 41; ++i) offsets.push_back(-0.6f + 1.2f * i / 40.0f);  // some miss the ball
  return offsets;
}

TEST(SpecularTree, EnergyIsBalancedOnEveryMaterial) {
  const SpecularTreeSettings settings{0.01f, 32};
  for (const std::string material : {"{type: glass, ior: 1.5}", "{type: glass, ior: 1.5, absorption: 1.5}",
                                     "{type: mirror, reflectance: 0.7}", "{type: glass, ior: 3.5}"}) {
    for (bool floor : {false, true}) {
      const Traced traced = trace_down(ball_scene(material, floor), offsets_across(), settings);
      const SpecularTreeStats& s = traced.stats;
      std::printf("%s, floor %d: started %.5f = missed %.5f + exited %.5f + dropped %.5f + absorbed %.5f\n",
                  material.c_str(), floor, s.started, s.missed, s.exited, s.dropped, s.absorbed);
      EXPECT_NEAR(s.started, s.missed + s.exited + s.dropped + s.absorbed, 1e-5 * s.started) << material << " floor " << floor;
      double outside = 0.0;  // the rays beside the ball meet nothing, or the floor
      for (float x : offsets_across()) outside += std::abs(x) >= 0.5f ? 1.0 : 0.0;
      EXPECT_NEAR(s.missed, floor ? 0.0 : outside * luminance(Color(1.0f)), 1e-6) << material;
      EXPECT_EQ(s.started, 41.0 * luminance(Color(1.0f)));
      // Without a floor nothing is met by a diffuse surface; with it, what leaves downwards is.
      if (!floor && material.find("absorption") == std::string::npos && material.find("mirror") == std::string::npos) {
        EXPECT_EQ(s.absorbed, 0.0) << material;
      }
      if (floor) EXPECT_GT(s.absorbed, 0.0) << material;
      double carried = 0.0;
      for (const ExitRay& exit : traced.exits) carried += luminance(exit.energy);
      EXPECT_NEAR(carried, s.exited, 1e-6 * s.started) << "the exits carry what the stats count";
    }
  }
}

// The central ray: reflected straight back with R, and through the ball along its diameter with
// (1 - R)^2 exp(-sigma 2 r) on its first exit, R at normal incidence from either side.
TEST(SpecularTree, TheCentralRayCarriesTheClosedFormWeights) {
  const double r = 0.5, sigma = 1.5;
  for (double ior : {1.5, 3.5}) {
    for (double absorption : {0.0, sigma}) {
      const std::string material =
          "{type: glass, ior: " + std::to_string(ior) + ", absorption: " + std::to_string(absorption) + "}";
      const Traced traced = trace_down(ball_scene(material, false), {0.0f}, SpecularTreeSettings{0.0f, 32});
      const double reflectance = normal_reflectance(ior);
      const double through = (1.0 - reflectance) * (1.0 - reflectance) * std::exp(-absorption * 2.0 * r);
      bool saw_reflection = false, saw_pass = false;
      for (const ExitRay& exit : traced.exits) {
        if (exit.depth == 1) {
          saw_reflection = true;
          EXPECT_NEAR(exit.energy.r, reflectance, 1e-5) << material;
          EXPECT_GT(exit.direction.y, 0.999f);
        }
        if (exit.depth == 2) {
          saw_pass = true;
          EXPECT_NEAR(exit.energy.r, through, 1e-5) << material;
          EXPECT_LT(exit.direction.y, -0.999f);
        }
      }
      EXPECT_TRUE(saw_reflection && saw_pass) << material;
      // Every bounce inside keeps R and the chord's attenuation: what leaves in all is, summed as a
      // geometric series, R + (1 - R)^2 a / (1 - R a), a = exp(-sigma 2 r); at min_energy 0 only
      // max_depth drops anything (R^31 of it).
      const double a = std::exp(-absorption * 2.0 * r);
      const double leaving = reflectance + (1.0 - reflectance) * (1.0 - reflectance) * a / (1.0 - reflectance * a);
      double exited = 0.0;
      for (const ExitRay& exit : traced.exits) exited += exit.energy.r;
      EXPECT_NEAR(exited, leaving, 1e-5) << material;
    }
  }
}

TEST(SpecularTree, AMirrorReflectsItsReflectanceAndAbsorbsTheRest) {
  const Traced traced = trace_down(ball_scene("{type: mirror, reflectance: 0.7}", false), offsets_across(), SpecularTreeSettings{});
  double hit = 0.0;
  for (const ExitRay& exit : traced.exits) {
    EXPECT_EQ(exit.depth, 1);
    EXPECT_NEAR(exit.energy.r, 0.7f, 1e-6f);
    hit += 1.0;
  }
  double inside = 0.0;
  for (float x : offsets_across()) inside += std::abs(x) < 0.5f ? 1.0 : 0.0;
  EXPECT_EQ(hit, inside);  // one exit for each ray that meets the ball
  EXPECT_NEAR(traced.stats.exited, 0.7 * hit * luminance(Color(1.0f)), 1e-5);
  EXPECT_NEAR(traced.stats.absorbed, 0.3 * hit * luminance(Color(1.0f)), 1e-5);
}

// Branches below min_energy are dropped and counted, never redistributed.
TEST(SpecularTree, TheThresholdDropsAndCounts) {
  const Scene scene = ball_scene("{type: glass, ior: 1.5}", false);
  const Traced fine = trace_down(scene, offsets_across(), SpecularTreeSettings{0.0f, 64});
  const Traced coarse = trace_down(scene, offsets_across(), SpecularTreeSettings{0.05f, 64});
  EXPECT_LT(fine.stats.dropped, 1e-6 * fine.stats.started);
  EXPECT_GT(coarse.stats.dropped, 0.0);
  EXPECT_NEAR(coarse.stats.exited + coarse.stats.dropped, fine.stats.exited, 1e-5 * fine.stats.started);
  EXPECT_LT(coarse.exits.size(), fine.exits.size());
}

}  // namespace
}  // namespace causticbench
