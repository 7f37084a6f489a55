// CausticPhotonTracer with explicit lights and targets (what precomputing methods shoot through), and
// the scene descriptions that key their cached builds. Links only causticbench_core.
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include <gtest/gtest.h>

#include "core/photon_tracer.h"
#include "core/scene.h"
#include "core/scene_description.h"
#include "core/tracer.h"

namespace causticbench {
namespace {

Scene scene_from_yaml(const std::string& yaml, const std::string& folder = ".") {
  return load_scene_from_string(yaml, "test.yaml", folder);
}

struct TraceResult {
  std::vector<Photon> photons;
  PhotonStats stats;
};

TraceResult trace(const CausticPhotonTracer& photon_tracer, uint64_t count) {
  TraceResult result;
  photon_tracer.trace(0, count, result.photons, result.stats);
  return result;
}

// Deposited power (red channel) within `radius` of `center` on the floor, and how many photons carry it.
struct Region {
  double power = 0.0;
  size_t photons = 0;
};

Region region(const std::vector<Photon>& photons, Vec3 center, float radius) {
  Region result;
  for (const Photon& photon : photons) {
    if (glm::length(photon.position - center) < radius) {
      result.power += photon.power.r;
      ++result.photons;
    }
  }
  return result;
}

double total_power(const std::vector<Photon>& photons) {
  double sum = 0.0;
  for (const Photon& photon : photons) sum += photon.power.r;
  return sum;
}

const char* const kGlassSphere = R"(
camera: {position: [0, 2.0, 2.0], look_at: [0, 0.1, 0], fov_degrees: 35, resolution: [40, 40]}
lights: [{type: directional, direction: [0.3, -1, 0.2], irradiance: [1.5, 1, 0.5]}]
objects:
  - shape: {type: quad, size: [6, 6]}
    material: {type: diffuse, albedo: 0.8}
  - shape: {type: sphere, radius: 0.4}
    material: {type: glass, ior: 1.5}
    transform: {translate: [0, 0.6, 0]}
  - shape: {type: box, size: [0.3, 0.3, 0.3]}
    material: {type: mirror, reflectance: 0.9}
    transform: {translate: [1, 0.3, -0.5], rotate: [0, 30, 0]}
)";

void expect_same_photons(const TraceResult& expected, const TraceResult& actual) {
  EXPECT_EQ(expected.stats.emitted, actual.stats.emitted);
  EXPECT_EQ(expected.stats.deposited, actual.stats.deposited);
  EXPECT_EQ(expected.stats.rays, actual.stats.rays);
  ASSERT_EQ(expected.photons.size(), actual.photons.size());
  // Photon is four Vec3 of floats with no padding: equal bytes is bit-identical output.
  static_assert(sizeof(Photon) == 4 * sizeof(Vec3));
  EXPECT_EQ(0, std::memcmp(expected.photons.data(), actual.photons.data(), expected.photons.size() * sizeof(Photon)));
}

// An explicit copy of the scene's light, aimed at the scene's specular objects, is the default tracer.
TEST(PhotonTracer, ExplicitSceneLightAndTargetsMatchTheDefaultBitForBit) {
  Scene scene = scene_from_yaml(kGlassSphere);
  SceneFrame frame(scene, 0);
  Tracer tracer(frame);
  const PhotonTracerSettings settings{7};
  TraceResult expected = trace(CausticPhotonTracer(tracer, settings), 50000);
  ASSERT_GT(expected.photons.size(), 1000u);

  // The same light built from its parameters: towards the light is the reverse of its travel.
  const Light& scene_light = scene.lights[0];
  PhotonLights built;
  built.add_directional(-Vec3(scene_light.direction.at(0)), scene_light.irradiance, scene_light.solid_angle);
  CausticPhotonTracer from_parameters(tracer, settings, built.frames(), frame.specular_objects());
  EXPECT_EQ(from_parameters.aimed_flux(), CausticPhotonTracer(tracer, settings).aimed_flux());
  expect_same_photons(expected, trace(from_parameters, 50000));

  // The scene's posed light, copied.
  PhotonLights copied;
  copied.add(frame.lights[0]);
  expect_same_photons(expected, trace(CausticPhotonTracer(tracer, settings, copied.frames(), {1, 2}), 50000));

  // Photon i draws only from Random(seed, i): one at a time, in order, on this thread, is the same.
  TraceResult one_by_one;
  for (uint64_t index = 0; index < 50000; ++index) {
    from_parameters.trace_one(index, one_by_one.photons, one_by_one.stats);
  }
  expect_same_photons(expected, one_by_one);
}

// trace_segments walks the path trace_one walks: every photon trace_one deposits ends a segment of
// the same path carrying the same power (the segment into a receiver is in air here), and both
// count the same rays.
TEST(PhotonTracer, SegmentsFollowThePathsPhotonsTake) {
  Scene scene = scene_from_yaml(kGlassSphere);
  SceneFrame frame(scene, 0);
  Tracer tracer(frame);
  const CausticPhotonTracer photon_tracer(tracer, PhotonTracerSettings{3});
  size_t matched = 0, photons_total = 0, segments_total = 0;
  for (uint64_t index = 0; index < 5000; ++index) {
    std::vector<Photon> photons;
    PhotonStats photon_stats, segment_stats;
    photon_tracer.trace_one(index, photons, photon_stats);
    std::vector<PathSegment> segments;
    photon_tracer.trace_segments(index, segment_stats, [&](const PathSegment& segment) { segments.push_back(segment); });
    EXPECT_EQ(photon_stats.rays, segment_stats.rays);
    for (const Photon& photon : photons) {
      for (const PathSegment& segment : segments) {
        if (!std::isfinite(segment.length)) continue;
        const Vec3 end = segment.origin + segment.direction * segment.length;
        if (glm::length(end - photon.position) < 1e-4f && segment.power == photon.power) {
          ++matched;
          break;
        }
      }
    }
    photons_total += photons.size();
    segments_total += segments.size();
  }
  ASSERT_GT(photons_total, 500u);
  EXPECT_EQ(matched, photons_total);
  EXPECT_GT(segments_total, photons_total);  // paths through the sphere have a segment inside it too
}

TEST(PhotonTracer, PhotonLightsFramesStayValidAsLightsAreAddedAndMoved) {
  PhotonLights lights;
  // Enough lights that a vector of Light would have reallocated many times.
  for (int i = 0; i < 200; ++i) lights.add_directional(Vec3(0, 1, 0), Color(static_cast<float>(i)));
  PhotonLights moved = std::move(lights);
  ASSERT_EQ(moved.frames().size(), 200u);
  for (int i = 0; i < 200; ++i) {
    const LightFrame& frame = moved.frames()[i];
    ASSERT_NE(frame.light, nullptr);
    EXPECT_EQ(frame.light->irradiance.r, static_cast<float>(i));
    EXPECT_EQ(frame.direction_to_light, Vec3(0, 1, 0));
    EXPECT_EQ(frame.light->direction.at(0), glm::dvec3(0, -1, 0));  // the way light travels
  }
  moved.add_point(Vec3(1, 2, 3), Color(4.0f), 0.5);
  const LightFrame& point = moved.frames().back();
  EXPECT_EQ(point.kind, LightKind::point);
  EXPECT_EQ(point.position, Vec3(1, 2, 3));
  EXPECT_EQ(point.radius, 0.5f);
  EXPECT_EQ(point.light->intensity, Color(4.0f));
  EXPECT_THROW(moved.add_directional(Vec3(0.0f), Color(1.0f)), std::invalid_argument);
  EXPECT_THROW(moved.add_point(Vec3(0.0f), Color(1.0f), -1.0), std::invalid_argument);
}

// Two glass spheres 6 apart over a floor, lit straight down, each focusing onto the floor below it.
// A wall between them stops the light that one sphere scatters sideways (grazing reflections,
// internal bounces) from reaching the other's caustic, so every photon near a sphere's focus came
// through that sphere.
const char* const kTwoSpheres = R"(
camera: {position: [0, 6, 6], look_at: [0, 0, 0], resolution: [16, 16]}
lights: [{type: directional, direction: [0, -1, 0], irradiance: 1}]
objects:
  - shape: {type: quad, size: [12, 4]}
    material: {type: diffuse}
  - name: wall
    shape: {type: quad, size: [3, 4]}
    material: {type: diffuse}
    transform: {translate: [0, 1.5, 0], rotate: [0, 0, 90]}
  - name: a
    shape: {type: sphere, radius: 0.4}
    material: {type: glass, ior: 1.5}
    transform: {translate: [-3, 0.6, 0]}
  - name: b
    shape: {type: sphere, radius: 0.4}
    material: {type: glass, ior: 1.5}
    transform: {translate: [3, 0.6, 0]}
)";

TEST(PhotonTracer, AimingAtOneObjectSendsExactlyItsCrossSectionsFluxAndOnlyThroughIt) {
  Scene scene = scene_from_yaml(kTwoSpheres);
  SceneFrame frame(scene, 0);
  Tracer tracer(frame);
  const int sphere_a = 2, sphere_b = 3;
  const Color irradiance(1.5f, 2.0f, 0.5f);
  PhotonLights lights;
  lights.add_directional(Vec3(0, 1, 0), irradiance);
  CausticPhotonTracer at_a(tracer, PhotonTracerSettings{3}, lights.frames(), {sphere_a});

  // The flux through the bounding sphere's disk: luminance(E) pi r^2, to float rounding. The bounding
  // sphere is the sphere's own, 1e-4 larger, so it is also E pi 0.4^2 within 3e-4.
  const double radius = frame.bounds[sphere_a].radius;
  const double luminance_e = 0.2126 * 1.5 + 0.7152 * 2.0 + 0.0722 * 0.5;
  EXPECT_NEAR(at_a.target_cross_section(), kPiDouble * radius * radius, 1e-12);
  EXPECT_NEAR(at_a.target_cross_section(), kPiDouble * 0.4 * 0.4, 3e-4 * kPiDouble * 0.4 * 0.4);
  EXPECT_NEAR(at_a.aimed_flux(), luminance_e * kPiDouble * radius * radius, 1e-6 * at_a.aimed_flux());

  const Vec3 focus_a(-3, 0, 0), focus_b(3, 0, 0);
  TraceResult through_a = trace(at_a, 100000);
  Region near_a = region(through_a.photons, focus_a, 1.5f), near_b = region(through_a.photons, focus_b, 1.5f);
  EXPECT_EQ(near_b.photons, 0u);
  // Most of what passes through a glass sphere is refracted into its focus below it.
  EXPECT_GT(region(through_a.photons, focus_a, 0.5f).power, 0.7 * total_power(through_a.photons));
  EXPECT_GT(near_a.photons, 50000u);

  // And the other way round, and both by default: both foci do receive caustics when aimed at.
  CausticPhotonTracer at_b(tracer, PhotonTracerSettings{3}, lights.frames(), {sphere_b});
  TraceResult through_b = trace(at_b, 100000);
  EXPECT_EQ(region(through_b.photons, focus_a, 1.5f).photons, 0u);
  EXPECT_GT(region(through_b.photons, focus_b, 1.5f).photons, 50000u);
  TraceResult through_both = trace(CausticPhotonTracer(tracer, PhotonTracerSettings{3}), 100000);
  EXPECT_GT(region(through_both.photons, focus_a, 1.5f).photons, 20000u);
  EXPECT_GT(region(through_both.photons, focus_b, 1.5f).photons, 20000u);
}

TEST(PhotonTracer, RejectsTargetsThatAreNotObjectsOnce) {
  Scene scene = scene_from_yaml(kTwoSpheres);
  SceneFrame frame(scene, 0);
  Tracer tracer(frame);
  PhotonLights lights;
  lights.add_directional(Vec3(0, 1, 0), Color(1.0f));
  EXPECT_THROW(CausticPhotonTracer(tracer, {}, lights.frames(), {-1}), std::invalid_argument);
  EXPECT_THROW(CausticPhotonTracer(tracer, {}, lights.frames(), {4}), std::invalid_argument);
  EXPECT_THROW(CausticPhotonTracer(tracer, {}, lights.frames(), {2, 2}), std::invalid_argument);
  // A diffuse object is a valid target (nothing caustic comes of it, but the aim is what was asked).
  EXPECT_NO_THROW(CausticPhotonTracer(tracer, {}, lights.frames(), {0, 3}));
  // No targets: photons are counted as emitted and carry nothing.
  CausticPhotonTracer nothing(tracer, {}, lights.frames(), {});
  EXPECT_FALSE(nothing.has_targets());
  TraceResult none = trace(nothing, 1000);
  EXPECT_EQ(none.stats.emitted, 1000u);
  EXPECT_TRUE(none.photons.empty());
}

// A flat mirror (reflectance 1) of area 1, and a wall that catches everything it reflects under a
// directional light at 45 degrees.
const char* const kMirrorAndWall = R"(
camera: {position: [3, 3, 3], look_at: [0, 0, 0], resolution: [8, 8]}
lights: [{type: directional, direction: [0, -1, 0], irradiance: 1}]
objects:
  - name: mirror
    shape: {type: quad, size: [1, 1]}
    material: {type: mirror, reflectance: 1}
  - name: wall
    shape: {type: quad, size: [10, 10]}
    material: {type: diffuse}
    transform: {translate: [-2, 2, 0], rotate: [0, 0, -90]}
)";

// A flat mirror (reflectance 1) of area 1 under a directional light at 45 degrees, and a wall that
// catches everything it reflects. The mirror intercepts E A cos(45) W, and all of it must be deposited.
TEST(PhotonTracer, MirrorQuadDepositsTheFluxThroughItsProjectedArea) {
  Scene scene = scene_from_yaml(kMirrorAndWall);
  SceneFrame frame(scene, 0);
  Tracer tracer(frame);
  const int mirror = 0;
  const double irradiance = 2.0;
  PhotonLights lights;
  lights.add_directional(Vec3(1, 1, 0), Color(static_cast<float>(irradiance)));
  CausticPhotonTracer photon_tracer(tracer, PhotonTracerSettings{11}, lights.frames(), {mirror});
  const uint64_t emitted = 1000000;
  TraceResult result = trace(photon_tracer, emitted);
  ASSERT_EQ(result.stats.emitted, emitted);

  const double expected = irradiance * 1.0 * std::sqrt(0.5);
  const double measured = total_power(result.photons) / static_cast<double>(emitted);
  // Every photon carries E pi r^2 (one target, reflectance 1), and it hits the mirror with
  // probability p = A cos / (pi r^2): the estimate is binomial, with relative standard deviation
  // sqrt((1 - p) / (p N)), about 0.11% here. Four of those bound it (fixed seed; a 6e-5 chance
  // for an arbitrary seed).
  const double radius = frame.bounds[mirror].radius;
  const double p = 1.0 * std::sqrt(0.5) / (kPiDouble * radius * radius);
  const double relative_sigma = std::sqrt((1.0 - p) / (p * static_cast<double>(emitted)));
  EXPECT_NEAR(measured, expected, 4.0 * relative_sigma * expected)
      << "deposited " << result.photons.size() << " of " << emitted << ", p " << p;
  // Each deposit is one mirror hit, so the count tells the same story with no weights involved.
  EXPECT_NEAR(static_cast<double>(result.photons.size()) / emitted, p, 4.0 * relative_sigma * p);
}

// The same mirror under stratified emission (PhotonTracerSettings::stratified_pass_size): each pass of
// 16384 photons is an independent, unbiased replicate of the deposited flux, and its spread is far below
// the binomial spread of independent photons, since the pass's aiming points cover the disk evenly and
// only those near the mirror's outline can fall either way (measured about 1/100 of the variance; asserted
// below a tenth). The mean of 200 passes is the projected flux within four of its standard errors.
TEST(PhotonTracer, StratifiedEmissionIsUnbiasedAndSpreadsLessThanIndependentPhotons) {
  Scene scene = scene_from_yaml(kMirrorAndWall);
  SceneFrame frame(scene, 0);
  Tracer tracer(frame);
  const double irradiance = 2.0;
  PhotonLights lights;
  lights.add_directional(Vec3(1, 1, 0), Color(static_cast<float>(irradiance)));
  const uint64_t per_pass = 16384;
  const int passes = 200;
  PhotonTracerSettings settings{11};
  settings.stratified_pass_size = per_pass;
  CausticPhotonTracer photon_tracer(tracer, settings, lights.frames(), {0});
  double sum = 0.0, squares = 0.0;
  for (int pass = 0; pass < passes; ++pass) {
    TraceResult result;
    photon_tracer.trace(static_cast<uint64_t>(pass) * per_pass, per_pass, result.photons, result.stats);
    const double estimate = total_power(result.photons) / static_cast<double>(per_pass);
    sum += estimate;
    squares += estimate * estimate;
  }
  const double mean = sum / passes, variance = (squares / passes - mean * mean) * passes / (passes - 1.0);
  const double expected = irradiance * std::sqrt(0.5);
  EXPECT_NEAR(mean, expected, 4.0 * std::sqrt(variance / passes));
  // Independent photons: each carries E pi r^2 with probability p, so a pass's variance is
  // (E pi r^2)^2 p (1 - p) / N.
  const double radius = frame.bounds[0].radius, carried = irradiance * kPiDouble * radius * radius;
  const double p = expected / carried;
  const double independent = carried * carried * p * (1.0 - p) / static_cast<double>(per_pass);
  EXPECT_LT(variance, 0.1 * independent) << "variance " << variance << " against " << independent << " independent";
}

const char* const kDescribedScene = R"(
camera: {position: [0, 2, 2], look_at: [0, 0, 0], fov_degrees: 35, resolution: [40, 40]}
lights: [{type: directional, direction: [0.3, -1, 0.2], irradiance: 1}]
objects:
  - shape: {type: quad, size: [6, 6]}
    material: {type: diffuse, albedo: 0.8}
  - shape: {type: sphere, radius: 0.4}
    material: {type: glass, ior: 1.5}
    transform: {translate: [0, 0.6, 0]}
  - shape: {type: mesh, asset: piece.obj}
    material: {type: mirror}
    transform: {translate: [1, 0.5, 0]}
)";

// A tetrahedron; `apex` moves its top vertex without changing the vertex or triangle count.
void write_tetrahedron(const std::filesystem::path& folder, double apex) {
  std::filesystem::create_directories(folder);
  std::ofstream file(folder / "piece.obj");
  file << "v 0 0 0\nv 1 0 0\nv 0 0 1\nv 0 " << apex << " 0\n"
       << "f 1 2 3\nf 1 4 2\nf 1 3 4\nf 2 4 3\n";
}

std::string replaced(std::string text, const std::string& from, const std::string& to) {
  size_t at = text.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  return at == std::string::npos ? text : text.replace(at, from.size(), to);
}

TEST(SceneDescription, ChangesWithWhatPhotonsMeetAndNotWithTheCamera) {
  const std::filesystem::path root = std::filesystem::path(::testing::TempDir()) / "scene_description";
  const std::string folder = (root / "first").string(), other_folder = (root / "second").string();
  write_tetrahedron(folder, 1.0);
  write_tetrahedron(other_folder, 1.25);
  const nlohmann::json content = scene_content_json(scene_from_yaml(kDescribedScene, folder));
  auto changed = [&](const std::string& from, const std::string& to) {
    return scene_content_json(scene_from_yaml(replaced(kDescribedScene, from, to), folder));
  };

  EXPECT_EQ(content, scene_content_json(scene_from_yaml(kDescribedScene, folder)));
  EXPECT_EQ(content, changed("position: [0, 2, 2], look_at: [0, 0, 0], fov_degrees: 35, resolution: [40, 40]",
                             "position: [1, 3, 2], look_at: [0, 0.2, 0], fov_degrees: 50, resolution: [256, 128]"));
  Scene resized = scene_from_yaml(kDescribedScene, folder);
  set_resolution(resized, 300, 200);
  EXPECT_EQ(content, scene_content_json(resized));

  EXPECT_NE(content, changed("ior: 1.5", "ior: 1.33"));
  EXPECT_NE(content, changed("radius: 0.4", "radius: 0.41"));
  EXPECT_NE(content, changed("direction: [0.3, -1, 0.2]", "direction: [0.3, -1, 0.25]"));
  EXPECT_NE(content, changed("translate: [1, 0.5, 0]", "translate: [1, 0.5, 0.01]"));
  // The same asset name and the same counts, another file: only the mesh hashes tell them apart.
  nlohmann::json other_mesh = scene_content_json(scene_from_yaml(kDescribedScene, other_folder));
  EXPECT_NE(content, other_mesh);
  EXPECT_EQ(content["objects"][2]["shape"]["vertices"], other_mesh["objects"][2]["shape"]["vertices"]);
  EXPECT_EQ(content["objects"][2]["shape"]["triangles"], other_mesh["objects"][2]["shape"]["triangles"]);
  EXPECT_NE(content["objects"][2]["shape"]["positions_hash"], other_mesh["objects"][2]["shape"]["positions_hash"]);
  // Parameters a kind does not read are not part of it: a sphere has no height.
  EXPECT_FALSE(content["objects"][1]["shape"].contains("height"));
  const nlohmann::json glass{{"kind", "glass"}, {"ior", 1.5}, {"absorption", {0, 0, 0}}};
  EXPECT_EQ(content["objects"][1]["material"], glass);
}

TEST(SceneDescription, StaticUnlessALightAnObjectOrAShapeMoves) {
  auto with = [](const std::string& from, const std::string& to) {
    return scene_from_yaml(replaced(kGlassSphere, from, to));
  };
  EXPECT_TRUE(scene_is_static(scene_from_yaml(kGlassSphere)));
  // A moving camera changes the view, not the scene.
  EXPECT_TRUE(scene_is_static(with("resolution: [40, 40]}",
                                   "resolution: [40, 40], animation: {keyframes: "
                                   "[{frame: 0, position: [0, 2, 2]}, {frame: 9, position: [1, 2, 2]}]}}")));
  Scene animated_light = with("irradiance: [1.5, 1, 0.5]}",
                              "irradiance: [1.5, 1, 0.5], animation: {keyframes: "
                              "[{frame: 0, direction: [0.3, -1, 0.2]}, {frame: 9, direction: [0, -1, 0]}]}}");
  EXPECT_FALSE(scene_is_static(animated_light));
  // Every keyframe is part of the description, so the animated light's differs from the static one's.
  EXPECT_NE(scene_content_json(animated_light), scene_content_json(scene_from_yaml(kGlassSphere)));
  EXPECT_EQ(light_json(animated_light.lights[0])["direction"]["keyframes"].size(), 2u);
  EXPECT_FALSE(scene_is_static(with("transform: {translate: [0, 0.6, 0]}",
                                    "animation: {keyframes: [{frame: 0, translate: [0, 0.6, 0]}, "
                                    "{frame: 9, translate: [0, 0.8, 0]}]}")));
  EXPECT_FALSE(scene_is_static(with("{type: quad, size: [6, 6]}",
                                    "{type: water, size: [6, 6], resolution: [8, 8], waves: "
                                    "[{amplitude: 0.01, wavelength: 1, phase_per_frame_degrees: 10}]}")));
}

}  // namespace
}  // namespace causticbench
