// The CPU backend's speed-ups of csl's evaluation and what they must not change: the cull (render knob
// `cull`, methods/csl/spot_reach.h) leaves the image the same bit for bit while it skips pairs, and the
// vector lanes (render knob `lanes`, methods/csl/evaluation_lanes.h) agree with the scalar evaluation,
// per point on spot lights of every kind of profile and on whole frames, the float lanes with the double
// ones on whole frames, and the gathered lookups (methods/csl/tile_lookup.h) with the one-by-one lookups
// bit for bit. Their speed is measured by a command in methods/csl/README.md, not here.
#include <cmath>
#include <cstring>
#include <random>

#include <gtest/gtest.h>

#include "core/image_statistics.h"
#include "methods/csl/evaluation_lanes.h"
#include "methods/csl/spot_light.h"
#include "methods/csl/spot_reach.h"
#include "methods/csl/tile_lookup.h"
#include "methods/lifecycle.h"
#include "methods/registry.h"
#include "tests/test_support.h"

using namespace causticbench;
using namespace causticbench::csl;
using causticbench::testing::kSmallGlassSphere;
using causticbench::testing::replace_once;
using causticbench::testing::scene_from_yaml;

namespace {

PhaseKnobs csl_knobs(const std::vector<std::string>& knobs) { return causticbench::testing::method_knobs("csl", knobs); }

double counter(const CausticMethod& method, const std::string& name) {
  for (const auto& [key, value] : method.counters()) {
    if (key == name) return value;
  }
  ADD_FAILURE() << "no counter " << name;
  return 0.0;
}

// The largest per-pixel difference relative to the larger value (0 where both are 0).
double largest_relative_difference(const Image& a, const Image& b) {
  double largest = 0.0;
  for (size_t i = 0; i < a.values().size(); ++i) {
    const double x = a.values()[i], y = b.values()[i], scale = std::max(std::fabs(x), std::fabs(y));
    if (scale > 0.0) largest = std::max(largest, std::fabs(x - y) / scale);
  }
  return largest;
}

const std::vector<std::vector<std::string>> kEvaluationKnobs = {
    {}, {"intensity_correction=off"}, {"on_axis=epsilon", "axis_epsilon=0.05"}};

// On one prepared and updated instance, per evaluation knob set: cull on and off give the same image
// bit for bit on both paths while the cull skips pairs, the vector lanes agree with the scalar path, and
// `lanes: float` with the double lanes to the Vulkan kernel's bound (it computes the same geometry in
// float; methods/csl/README.md, "Agreement"): relMSE below 1e-5 and flux within 1e-4.
void expect_speedups_change_nothing(CausticMethod& method, const PosedFrame& frame, const std::string& what) {
  for (const std::vector<std::string>& set : kEvaluationKnobs) {
    std::string knobs;
    for (const std::string& knob : set) knobs += " " + knob;
    Image images[2][2];  // [lanes: scalar, vector][cull: off, on]
    double evaluations[2] = {0.0, 0.0};
    for (int vector = 0; vector < 2; ++vector) {
      for (int cull = 0; cull < 2; ++cull) {
        std::vector<std::string> with = set;
        with.push_back(vector ? "lanes=vector" : "lanes=scalar");
        with.push_back(cull ? "cull=on" : "cull=off");
        images[vector][cull] = method.render(frame.gbuffer, csl_knobs(with).render);
        evaluations[cull] = counter(method, "csl_evaluations");
      }
      const Image& culled = images[vector][1];
      const Image& whole = images[vector][0];
      ASSERT_EQ(culled.values().size(), whole.values().size());
      size_t differing = 0;
      for (size_t i = 0; i < culled.values().size(); ++i) {
        differing += std::memcmp(&culled.values()[i], &whole.values()[i], sizeof(float)) != 0;
      }
      EXPECT_EQ(differing, 0u) << what << knobs << (vector ? ", vector" : ", scalar") << ": the cull changed values";
      EXPECT_GT(masked_sum(whole, frame.gbuffer.receiver), 0.0) << what << knobs;
      // The cull does something: the receivers far from the caustic are skipped.
      EXPECT_LT(evaluations[1], 0.8 * evaluations[0]) << what << knobs;
      std::printf("%s%s, %s lanes: cull evaluates %.0f of %.0f pairs, %zu values differ\n", what.c_str(), knobs.c_str(),
                  vector ? "vector" : "scalar", evaluations[1], evaluations[0], differing);
    }
    const double relmse = relative_mse(images[1][1], images[0][1], frame.gbuffer.receiver);
    const double largest = largest_relative_difference(images[1][1], images[0][1]);
    std::printf("%s%s: vector against scalar lanes relMSE %.3g, largest relative difference %.3g\n", what.c_str(),
                knobs.c_str(), relmse, largest);
    EXPECT_LT(largest, 1e-6) << what << knobs;
    std::vector<std::string> in_float = set;
    in_float.push_back("lanes=float");
    const Image narrow = method.render(frame.gbuffer, csl_knobs(in_float).render);
    const double float_relmse = relative_mse(narrow, images[1][1], frame.gbuffer.receiver);
    const double flux = masked_sum(narrow, frame.gbuffer.receiver) / masked_sum(images[1][1], frame.gbuffer.receiver);
    std::printf("%s%s: float against double lanes relMSE %.3g, flux ratio %.9f\n", what.c_str(), knobs.c_str(),
                float_relmse, flux);
    EXPECT_LT(float_relmse, 1e-5) << what << knobs;
    EXPECT_NEAR(flux, 1.0, 1e-4) << what << knobs;
  }
}

// A spot light of `profile` off the origin, its axis tilted, with the `size` x `size` uint16 image `values`.
SpotLight tilted_spot_light(const Profile& profile, int size, const std::vector<float>& values) {
  SpotLight light;
  light.origin = Vec3(0.1f, -0.2f, 0.05f);
  light.axis = glm::normalize(Vec3(0.2f, 0.1f, 1.0f));
  set_plane_axes(light);
  light.profile = profile;
  light.image = IntensityImage(size, 1, 1.0f, values, IntensityImage::Precision::uint16);
  return light;
}

// A tile of 1 + tile_index % kTilePoints random points in front of `light`, within `spread` of its axis,
// with normals facing any way but mostly towards the light and footprint radii up to 0.06.
struct RandomTile {
  size_t count = 0;
  Vec3 points[kTilePoints], normals[kTilePoints];
  float footprints[kTilePoints];
  PointTile tile;
  TileRays rays;  // the tile's candidate rays of `lanes` (tile_rays), which both lanes tests compare on
};
RandomTile random_tile(const SpotLight& light, const LightLanes& lanes, const EvaluationSettings& settings,
                       int tile_index, float spread, std::mt19937& random) {
  std::uniform_real_distribution<float> uniform(-1.0f, 1.0f);
  RandomTile made;
  made.count = 1 + tile_index % kTilePoints;
  for (size_t j = 0; j < made.count; ++j) {
    const float height = 1.5f * uniform(random) + 1.0f;
    made.points[j] = light.origin + height * light.axis + spread * uniform(random) * light.u + spread * uniform(random) * light.v;
    made.normals[j] = glm::normalize(Vec3(uniform(random), uniform(random), uniform(random)) - 0.8f * light.axis);
    made.footprints[j] = 0.03f * (uniform(random) + 1.0f);
  }
  made.tile = make_tile(made.points, made.normals, made.footprints, made.count, settings);
  tile_rays(lanes, made.tile, made.rays);
  return made;
}

}  // namespace

// The glass sphere under a static light: its several spot lights, each culled to its own frustum.
TEST(CslCull, TheGlassSphereIsTheSameBitForBit) {
  const Scene scene = scene_from_yaml(kSmallGlassSphere);
  for (const char* precision : {"precision=uint16", "precision=float32"}) {
    const PhaseKnobs knobs = csl_knobs({"rays_per_side=96", "image_size=128", precision});
    std::unique_ptr<CausticMethod> method = find_method("csl").create();
    const RestPose rest(scene, {0});
    prepare_method(*method, rest.context(), knobs.build);
    ASSERT_GE(counter(*method, "spot_lights"), 3.0);
    const PosedFrame frame(scene, 0);
    method->update(frame.context(), knobs.frame);
    expect_speedups_change_nothing(*method, frame, std::string("glass sphere, ") + precision);
  }
}

// A dynamic light's interpolated frame: blended images, whose support is their sources'.
TEST(CslCull, AnInterpolatedFrameIsTheSameBitForBit) {
  const Scene moving = scene_from_yaml(causticbench::testing::small_glass_sphere_turning());
  const PhaseKnobs knobs = csl_knobs({"rays_per_side=48", "image_size=128", "tracking_rays_per_side=16", "tracking_steps=2"});
  std::unique_ptr<CausticMethod> method = find_method("csl").create();
  const RestPose rest(moving, {0, 1});
  prepare_method(*method, rest.context(), knobs.build);
  const PosedFrame frame(moving, 1);
  method->update(frame.context(), knobs.frame);
  ASSERT_GT(counter(*method, "interpolated_spot_lights"), 0.0);
  expect_speedups_change_nothing(*method, frame, "interpolated frame");
}

// Point by point (spheres of radius 0, where the bound is tightest), on spot lights of every kind of
// profile with an image lit only in an off-centre disk: no point with light is culled, and most points
// without light are (the bound is not vacuous).
TEST(CslCull, NoLitPointIsCulled) {
  const std::vector<Profile> profiles = {{0.8, 0.5}, {0.8, 0.0}, {0.0, 0.0}, {-1.5, 0.0}, {2.0, 3.0}, {1e-9, 1e6}, {-0.7, 0.4}};
  std::mt19937 random(5);
  std::uniform_real_distribution<float> uniform(-1.0f, 1.0f);
  const int size = 64;
  std::vector<float> values(size * size, 0.0f);
  for (int j = 0; j < size; ++j) {
    for (int i = 0; i < size; ++i) values[j * size + i] = (i - 36) * (i - 36) + (j - 30) * (j - 30) < 60 ? 1.0f : 0.0f;
  }
  size_t lit = 0, dark = 0, culled = 0;
  for (const Profile& profile : profiles) {
    const SpotLight light = tilted_spot_light(profile, size, values);
    ASSERT_LT(light.image.support_radius(), 0.8 * light.image.max_radius());
    const SpotReach reach(light, light.image.support_radius());
    EvaluationSettings settings;
    settings.on_axis = OnAxis::epsilon;
    settings.axis_epsilon = 1e-4;
    for (int k = 0; k < 20000; ++k) {
      const float height = 1.5f * uniform(random) + 1.2f;
      const Vec3 point = light.origin + height * light.axis + 2.0f * uniform(random) * light.u + 2.0f * uniform(random) * light.v;
      const Vec3 normal = -light.axis;
      float value[3] = {0.0f, 0.0f, 0.0f};
      light.evaluate(point, normal, 0.0f, settings, value);
      const bool kept = reach.may_reach(glm::dvec3(point), 0.0, settings.axis_epsilon);
      if (value[0] != 0.0f) {
        ++lit;
        EXPECT_TRUE(kept) << "kappa " << profile.kappa << " beta " << profile.beta << ": a lit point is culled";
      } else {
        ++dark;
        culled += !kept;
      }
    }
  }
  std::printf("%zu lit points, %zu dark of which %zu culled\n", lit, dark, culled);
  EXPECT_GT(lit, 1000u);
  EXPECT_GT(culled, dark / 3);
}

// Point by point, the lanes against evaluate_spot_light on spot lights of every kind of profile
// (converging, perfect focus, collimated, diverging, beta = 0 and huge), with a non-uniform uint16
// image, at points in front of, behind, near and far from the light plane and axis, normals facing
// any way, both on-axis treatments and Eq. 4 on and off.
TEST(CslLanes, AgreeWithTheScalarEvaluationPointByPoint) {
  const std::vector<Profile> profiles = {{0.8, 0.5}, {0.8, 0.0}, {0.0, 0.0}, {-1.5, 0.0}, {2.0, 3.0}, {1e-9, 1e6}, {-0.7, 0.4}};
  std::mt19937 random(11);
  const int size = 64;
  std::vector<float> values(size * size);
  for (int j = 0; j < size; ++j) {
    for (int i = 0; i < size; ++i) values[j * size + i] = (i - 20) * (i - 20) + (j - 30) * (j - 30) < 500 ? 1.0f + 0.01f * i : 0.0f;
  }
  size_t compared = 0, lit = 0, identical = 0;
  double largest = 0.0;
  for (const Profile& profile : profiles) {
    const SpotLight light = tilted_spot_light(profile, size, values);
    for (const bool correction : {true, false}) {
      for (const OnAxis on_axis : {OnAxis::integrate, OnAxis::epsilon}) {
        EvaluationSettings settings;
        settings.intensity_correction = correction;
        settings.on_axis = on_axis;
        settings.axis_epsilon = 0.02;
        const LightLanes lanes = light_lanes(light, light.image.max_radius(), correction);
        for (int tile_index = 0; tile_index < 200; ++tile_index) {
          // Mostly within a few radii of the axis; some on the axis.
          const RandomTile t = random_tile(light, lanes, settings, tile_index, tile_index % 5 == 0 ? 0.01f : 2.0f, random);
          const TileRays& rays = t.rays;
          for (size_t j = 0; j < t.count; ++j) {
            float scalar[3] = {0.0f, 0.0f, 0.0f}, vector[3] = {0.0f, 0.0f, 0.0f};
            light.evaluate(t.points[j], t.normals[j], t.footprints[j], settings, scalar);
            tile_value(light, StoredImage(light.image), rays, j, t.points[j], t.normals[j], t.footprints[j], settings, vector);
            ++compared;
            lit += scalar[0] > 0.0f;
            identical += std::memcmp(scalar, vector, sizeof(float)) == 0;
            const double scale = std::max(std::fabs(scalar[0]), std::fabs(vector[0]));
            const double difference = scale > 0.0 ? std::fabs(scalar[0] - vector[0]) / scale : 0.0;
            largest = std::max(largest, difference);
            EXPECT_LE(difference, 1e-6) << "kappa " << profile.kappa << " beta " << profile.beta << ": scalar "
                                        << scalar[0] << ", vector " << vector[0];
          }
        }
      }
    }
  }
  std::printf("%zu points (%zu lit): %zu identical, largest relative difference %.3g\n", compared, lit, identical, largest);
  EXPECT_GT(lit, compared / 4);  // most points are lit: the comparison is not of zeros
}

// The gathered lookups (tile_lookup.h) against tile_value's one ray at a time, bit for bit, on uint16 and
// float32 images lit up to their edges, so that rays land inside the texels, on the border squares
// (the scalar lookup's lanes) and beyond the image, at points with and without near-axis lanes.
TEST(CslLanes, GatheredLookupsAreTheSameBitForBit) {
  if (!tile_lookups_apply(IntensityImage(2, 1, 1.0f, {1.0f, 1.0f, 1.0f, 1.0f}, IntensityImage::Precision::float32))) {
    GTEST_SKIP() << "no AVX2";
  }
  const std::vector<Profile> profiles = {{0.8, 0.5}, {0.0, 0.0}, {-1.5, 0.0}, {2.0, 3.0}};
  std::mt19937 random(17);
  const int size = 32;
  std::vector<float> values(size * size);
  for (int j = 0; j < size; ++j) {
    for (int i = 0; i < size; ++i) values[j * size + i] = 1.0f + 0.37f * ((i * 7 + j * 13) % 11);
  }
  size_t compared = 0, lit = 0, differing = 0, border = 0, beyond = 0;
  for (const IntensityImage::Precision precision : {IntensityImage::Precision::uint16, IntensityImage::Precision::float32}) {
    for (const Profile& profile : profiles) {
      SpotLight light = tilted_spot_light(profile, size, values);
      light.image = IntensityImage(size, 1, 1.0f, values, precision);
      EvaluationSettings settings;
      settings.axis_epsilon = 0.02;
      const LightLanes lanes = light_lanes(light, light.image.max_radius(), true);
      for (int tile_index = 0; tile_index < 400; ++tile_index) {
        const RandomTile t = random_tile(light, lanes, settings, tile_index, tile_index % 7 == 0 ? 0.02f : 2.5f, random);
        const TileRays& rays = t.rays;
        float gathered[kTilePoints] = {};
        tile_lookups(light.image, rays, t.count, gathered);
        for (size_t j = 0; j < t.count; ++j) {
          float one_by_one[3] = {0.0f, 0.0f, 0.0f};
          if ((rays.near_axis >> j) & 1u) continue;  // the scalar evaluation, in both
          tile_value(light, StoredImage(light.image), rays, j, t.points[j], t.normals[j], t.footprints[j], settings, one_by_one);
          ++compared;
          lit += one_by_one[0] > 0.0f;
          differing += std::memcmp(&gathered[j], one_by_one, sizeof(float)) != 0;
          EXPECT_EQ(gathered[j], one_by_one[0]) << "kappa " << profile.kappa << " beta " << profile.beta;
          // Where the rays landed: on a border square (fx or fy in [-1, 0) or [size - 1, size)) or beyond.
          for (int k = 0; k < TileRays::kCandidates; ++k) {
            if (!((rays.ray[k] >> j) & 1u)) continue;
            const float fx = (static_cast<float>(rays.x[k][j]) + 1.0f) * (size / 2.0f) - 0.5f;
            const float fy = (static_cast<float>(rays.y[k][j]) + 1.0f) * (size / 2.0f) - 0.5f;
            const bool outside = !(fx > -1.0f && fy > -1.0f && fx < size && fy < size);
            beyond += outside;
            border += !outside && (fx < 0.0f || fy < 0.0f || fx >= size - 1 || fy >= size - 1);
          }
        }
      }
    }
  }
  std::printf("%zu points (%zu lit): %zu differ; rays on border squares %zu, beyond the image %zu\n", compared, lit,
              differing, border, beyond);
  EXPECT_EQ(differing, 0u);
  EXPECT_GT(lit, compared / 4);
  EXPECT_GT(border, 20u);
  EXPECT_GT(beyond, 20u);
}
