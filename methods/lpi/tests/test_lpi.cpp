// lpi (Wyman 2003) as a method: against the reference, the light sample sets it chooses, a caustic
// that moves with its object, its build keys, and scenes and knobs at the extremes. The interface
// checks every method shares (determinism, build cache round trip, well-formed output) are in
// test_conformance.cpp; its storage and estimator in test_lpi_storage.cpp.
#include <cmath>

#include <fmt/format.h>
#include <gtest/gtest.h>

#include "core/errors.h"
#include "core/image_statistics.h"
#include "store/build_cache.h"
#include "methods/lifecycle.h"
#include "methods/lpi/light_samples.h"
#include "methods/registry.h"
#include "tests/test_support.h"

using namespace causticbench;
using causticbench::testing::kSmallGlassSphere;
using causticbench::testing::replace_once;
using causticbench::testing::scene_from_yaml;

namespace {

// Receivers within `radius` of `center`: where lpi sampled the caustic.
std::vector<uint8_t> inside_volume(const GBuffer& gbuffer, const Vec3& center, float radius) {
  std::vector<uint8_t> mask(gbuffer.pixel_count(), 0);
  for (size_t pixel = 0; pixel < gbuffer.pixel_count(); ++pixel) {
    mask[pixel] = gbuffer.receiver[pixel] && glm::length(gbuffer.position[pixel] - center) < radius;
  }
  return mask;
}

struct Agreement {
  double relmse, energy_ratio;
};

Agreement agreement(const FrameResult& method, const FrameResult& reference, const std::vector<uint8_t>& mask) {
  return {relative_mse(method.caustic, reference.caustic, mask),
          masked_sum(method.caustic, mask) / masked_sum(reference.caustic, mask)};
}

// Sum of |method - reference| over the sum of the reference, on the mask: an error that, unlike
// relMSE, does not weigh light spilled into the dark around a sharp edge above light that is right.
double relative_l1(const FrameResult& method, const FrameResult& reference, const std::vector<uint8_t>& mask) {
  double difference = 0.0, total = 0.0;
  for (size_t pixel = 0; pixel < mask.size(); ++pixel) {
    if (!mask[pixel]) continue;
    for (int c = 0; c < 3; ++c) {
      difference += std::fabs(method.caustic.at(pixel, c) - reference.caustic.at(pixel, c));
      total += reference.caustic.at(pixel, c);
    }
  }
  return difference / total;
}

ParamSet build_knobs(const std::vector<std::string>& knobs) {
  const MethodInfo& info = find_method("lpi").info();
  ParamDict dict;
  for (const std::string& knob : knobs) dict.set_assignment(knob, "test_lpi");
  return split_phases(dict.resolve(info.params, "lpi"), info.params).build;
}

}  // namespace

// The glass sphere under a directional light, one light sample (the light does not move): inside
// the sampled ball lpi's E_c agrees with the reference's. Measured (200,000 photons, reference 6 x
// 200,000, the volume at its scene-derived default since issue 32): paper orientation relMSE 0.159
// (grid 48^3) and 0.139 (24 shells, subdivision 5), energy 1.177 and 1.164: the cosine correction of
// Section 3.2 is an approximation for light that does not arrive along the line to the centre, and it
// over-counts here. That bias is bounded on both sides (1.12 to 1.24, 1.11 to 1.22): a change that made
// it vanish or grow is a change of the estimate, to be explained, not absorbed. The vector orientation:
// relMSE 0.011, energy 1.056. relMSE bounds about twice the measured; energy about twice the deviation.
// (Before issue 32's default volume it measured 0.137 / 0.136 / 0.006 and 1.10 / 1.14 / 0.97.)
TEST(Lpi, GlassSphereMatchesTheReferenceInsideTheVolume) {
  const Scene scene = scene_from_yaml(kSmallGlassSphere);
  const FrameResult reference = causticbench::testing::render(scene, "reference", causticbench::testing::kSmallSceneReferenceKnobs);
  const std::vector<uint8_t> mask = inside_volume(reference.gbuffer, Vec3(0.0f, 0.6f, 0.0f), 1.2f);
  struct Case {
    std::vector<std::string> knobs;
    double relmse, least_energy, most_energy;  // bounds: relMSE below, the energy ratio between
  };
  const std::vector<Case> cases = {{{"storage=grid", "grid_resolution=48", "orientation=paper"}, 0.32, 1.12, 1.24},
                                   {{"storage=shells", "shell_count=24", "shell_subdivision=5", "orientation=paper"},
                                    0.28, 1.11, 1.22},
                                   {{"storage=grid", "grid_resolution=48", "orientation=vector"}, 0.022, 0.89, 1.11}};
  for (Case run : cases) {
    std::string name;
    for (const std::string& knob : run.knobs) name += knob + " ";
    run.knobs.push_back("photons_per_sample=200000");
    const FrameResult lpi = causticbench::testing::render(scene, "lpi", run.knobs);
    EXPECT_EQ(lpi.method_record["objects"][0]["light_samples"], 1) << name;
    EXPECT_EQ(lpi.method_record["objects"][0]["light_sample_set"], "static") << name;
    const Agreement measured = agreement(lpi, reference, mask);
    std::printf("glass sphere, %s: relMSE %.4f, energy ratio %.4f\n", name.c_str(), measured.relmse, measured.energy_ratio);
    EXPECT_LT(measured.relmse, run.relmse) << name;
    EXPECT_GT(measured.energy_ratio, run.least_energy) << name;
    EXPECT_LT(measured.energy_ratio, run.most_energy) << name;
  }
}

// The ring with light samples over the whole sphere (light_samples: all) and the light exactly on
// one of them: that sample's volume alone is read, and its light is the reference's: energy within
// 8 % and relative L1 error below 0.7 (measured 0.46 and 1.001). relMSE is not the measure
// here: cells of 0.08 blur the ring's sharp shadow edges over pixels of 0.03, and the light spilled
// into the dark beside them gives relMSE near 80. The paper orientation loses most of the light
// inside the ring.
TEST(Lpi, RingAtALightSampleDirectionMatchesTheReference) {
  const lpi::LightSampleSet set = lpi::geodesic_samples(1, lpi::SampleAt::vertices);
  Vec3 chosen = set.directions[0];
  for (const Vec3& d : set.directions) {
    if (d.y > 0.5f && d.y < 0.95f && d.y > chosen.y) chosen = d;  // tilted, as a ring's cardioid needs
  }
  ASSERT_GT(chosen.y, 0.5f);
  const Scene scene = scene_from_yaml(fmt::format(R"(
camera: {{type: orthographic, position: [0, 3, 0], look_at: [0, 0, 0], up: [0, 0, 1], view_height: 2.4, resolution: [80, 80]}}
lights: [{{type: directional, direction: [{:.9g}, {:.9g}, {:.9g}], irradiance: 1}}]
objects:
  - shape: {{type: quad, size: [6, 6]}}
    material: {{type: diffuse, albedo: 0.8}}
  - shape: {{type: ring, radius: 0.6, height: 0.4}}
    material: {{type: mirror, reflectance: 0.9}}
    transform: {{translate: [0, 0.2, 0]}}
)",
                                                  -chosen.x, -chosen.y, -chosen.z));
  const FrameResult reference = causticbench::testing::render(scene, "reference", causticbench::testing::kSmallSceneReferenceKnobs);
  const std::vector<uint8_t> mask = inside_volume(reference.gbuffer, Vec3(0.0f, 0.2f, 0.0f), 3.0f * 0.6325f);
  for (const std::string orientation : {"orientation=vector", "orientation=paper"}) {
    const FrameResult lpi = causticbench::testing::render(scene, "lpi", {"light_samples=all", "light_subdivision=1", orientation,
                                                        "photons_per_sample=200000", "grid_resolution=48"});
    EXPECT_EQ(lpi.method_record["objects"][0]["light_samples"], 42);
    const Agreement measured = agreement(lpi, reference, mask);
    const double l1 = relative_l1(lpi, reference, mask);
    std::printf("ring at a light sample, %s: relative L1 %.4f, energy ratio %.4f (relMSE %.4f)\n", orientation.c_str(), l1,
                measured.energy_ratio, measured.relmse);
    if (orientation == "orientation=vector") {
      EXPECT_LT(l1, 0.7);
      EXPECT_NEAR(measured.energy_ratio, 1.0, 0.08);
    } else {
      // The paper's orientation takes light that crosses the ring towards its axis for light that
      // leaves it: most of the caustic inside the ring is lost (README, "Orientation").
      EXPECT_LT(measured.energy_ratio, 0.6);
    }
  }
}

// Rotational alignment (Section 5.2, steps A to F) is exact for a sphere: turning a neighbouring
// sample's volume about L x L_i by the angle between them gives the caustic of L itself. So with the
// light at the centre of a geodesic triangle (about 18 degrees from each of its three light samples)
// the aligned blend of 42 samples renders what one light sample exactly at the light renders, up to
// the grid's resampling of the turned points, while the barycentric blend of the same three volumes
// shows three displaced caustics (ghosting). Relative L1 against the exact sample, inside the sampled
// ball, measured: aligned 0.193 (energy 0.949), barycentric 1.02. The aligned residual is the grid's
// resampling, not photon noise: 0.184 at four times the photons, 0.076 at 64^3 (barycentric 1.09).
TEST(Lpi, AlignedBlendIsExactForTheGlassSphere) {
  const lpi::LightSampleSet set = lpi::geodesic_samples(1, lpi::SampleAt::vertices);
  const Vec3 original_light = glm::normalize(Vec3(-0.3f, 1.0f, -0.2f));  // towards kSmallGlassSphere's light
  Vec3 centre(0.0f);
  float best = -2.0f;
  for (const auto& corners : set.mesh->triangles()) {
    const Vec3 centroid = glm::normalize(set.directions[corners[0]] + set.directions[corners[1]] + set.directions[corners[2]]);
    if (glm::dot(centroid, original_light) > best) {
      best = glm::dot(centroid, original_light);
      centre = centroid;
    }
  }
  const Scene scene = scene_from_yaml(replace_once(kSmallGlassSphere, "direction: [0.3, -1, 0.2]",
                                                   fmt::format("direction: [{:.9g}, {:.9g}, {:.9g}]", -centre.x, -centre.y, -centre.z)));
  const std::vector<uint8_t> mask = inside_volume(causticbench::testing::render(scene, "lpi", {"photons_per_sample=1"}).gbuffer,
                                                  Vec3(0.0f, 0.6f, 0.0f), 1.2f);
  const std::vector<std::string> common = {"photons_per_sample=50000", "grid_resolution=32"};
  auto render = [&](std::vector<std::string> knobs) {
    knobs.insert(knobs.end(), common.begin(), common.end());
    return causticbench::testing::render(scene, "lpi", knobs);
  };
  const FrameResult exact = render({});
  ASSERT_EQ(exact.method_record["objects"][0]["light_samples"], 1);
  const FrameResult aligned = render({"light_samples=all", "light_subdivision=1", "blend=aligned"});
  const FrameResult barycentric = render({"light_samples=all", "light_subdivision=1", "blend=barycentric"});
  ASSERT_EQ(aligned.method_record["objects"][0]["light_samples"], 42);
  const double aligned_l1 = relative_l1(aligned, exact, mask), barycentric_l1 = relative_l1(barycentric, exact, mask);
  const Agreement aligned_agreement = agreement(aligned, exact, mask);
  std::printf("glass sphere between light samples: relative L1 against the exact sample, aligned %.4f (energy %.4f), barycentric %.4f\n",
              aligned_l1, aligned_agreement.energy_ratio, barycentric_l1);
  EXPECT_LT(aligned_l1, 0.3);
  EXPECT_NEAR(aligned_agreement.energy_ratio, 1.0, 0.1);
  EXPECT_GT(barycentric_l1, 0.6);
}

// Model only what the scene requires: a static light gets its one direction, a moving one the
// geodesic set (162 at subdivision 2), unless the object's symmetry says fewer suffice.
TEST(Lpi, ChoosesTheLightSamplesTheFramesNeed) {
  const std::string animated = replace_once(
      kSmallGlassSphere, "direction: [0.3, -1, 0.2], irradiance: 1",
      "direction: [0.3, -1, 0.2], irradiance: 1, animation: {keyframes: [{frame: 0, direction: [0.3, -1, 0.2]}, {frame: 1, direction: [-0.4, -1, 0]}]}");
  const Scene moving = scene_from_yaml("frames: 2\n" + animated);
  const std::vector<std::string> cheap = {"photons_per_sample=200", "grid_resolution=4"};
  auto samples = [&](const Scene& scene, std::vector<std::string> knobs, int frame) {
    knobs.insert(knobs.end(), cheap.begin(), cheap.end());
    const FrameResult result = causticbench::testing::render(scene, "lpi", knobs, frame);
    return std::make_pair(result.method_record["objects"][0]["light_samples"].get<int>(),
                          result.method_record["objects"][0]["light_sample_set"].get<std::string>());
  };
  EXPECT_EQ(samples(scene_from_yaml(kSmallGlassSphere), {}, 0), std::make_pair(1, std::string("static")));
  // One rendered frame of the animation: its light does not move within what is rendered.
  EXPECT_EQ(samples(moving, {}, 1), std::make_pair(1, std::string("static")));
  EXPECT_EQ(samples(scene_from_yaml(kSmallGlassSphere), {"light_samples=all"}, 0), std::make_pair(162, std::string("geodesic")));
  EXPECT_EQ(samples(scene_from_yaml(kSmallGlassSphere), {"light_samples=all", "light_sample_at=faces"}, 0),
            std::make_pair(320, std::string("geodesic")));
  EXPECT_EQ(samples(scene_from_yaml(kSmallGlassSphere), {"light_samples=all", "symmetry=axial"}, 0),
            std::make_pair(21, std::string("meridian")));
  EXPECT_EQ(samples(scene_from_yaml(kSmallGlassSphere), {"light_samples=all", "symmetry=spherical"}, 0),
            std::make_pair(1, std::string("spherical")));
}

// A mirror object moved and turned by its animation carries its caustic along: frame 1 of the
// animation renders as the same object standing still at frame 1's pose does, and both reuse one
// build (the build is in the object's own frame).
TEST(Lpi, TheCausticMovesAndTurnsWithItsObject) {
  const char* yaml = R"(
camera: {type: orthographic, position: [0.3, 3, 0], look_at: [0.3, 0, 0], up: [0, 0, 1], view_height: 3, resolution: [36, 36]}
lights: [{type: directional, direction: [0.2, -1, 0.1], irradiance: 1}]
objects:
  - shape: {type: quad, size: [8, 8]}
    material: {type: diffuse, albedo: 0.8}
  - shape: {type: ring, radius: 0.5, height: 0.3}
    material: {type: mirror, reflectance: 0.9}
)";
  const std::string still = std::string(yaml) + "    transform: {translate: [0.3, 0.15, 0.1], rotate: [0, 40, 0]}\n";
  const std::string moving = "frames: 2\n" + std::string(yaml) +
                             "    animation: {keyframes: [{frame: 0, translate: [0, 0.15, 0], rotate: [0, 0, 0]}, "
                             "{frame: 1, translate: [0.3, 0.15, 0.1], rotate: [0, 40, 0]}]}\n";
  // A fixed ball and orientation: auto fits both to where the receivers lie around the object, which
  // moving the object changes (its build key holds what it chose).
  const std::vector<std::string> knobs = {"photons_per_sample=50000", "grid_resolution=24", "light_samples=all",
                                          "light_subdivision=1", "blend=aligned", "volume_radius=3",
                                          "orientation=vector"};
  const FrameResult a = causticbench::testing::render(scene_from_yaml(still), "lpi", knobs);
  const FrameResult b = causticbench::testing::render(scene_from_yaml(moving), "lpi", knobs, 1);
  double largest = 0.0, difference = 0.0;
  for (size_t i = 0; i < a.caustic.values().size(); ++i) {
    largest = std::max(largest, static_cast<double>(a.caustic.values()[i]));
    difference = std::max(difference, std::fabs(static_cast<double>(a.caustic.values()[i]) - b.caustic.values()[i]));
  }
  ASSERT_GT(largest, 0.0);
  EXPECT_LT(difference, 1e-4 * largest);
  // And the build does not depend on where the object stands.
  const Scene still_scene = scene_from_yaml(still), moving_scene = scene_from_yaml(moving);
  RestPose rest_still(still_scene, {0});
  RestPose rest_moving(moving_scene, {0, 1});
  std::unique_ptr<CausticMethod> probe = create_method("lpi");
  const ParamSet build = build_knobs(knobs);
  EXPECT_EQ(probe->build_cache()->build_dependencies(rest_still.context(), build), probe->build_cache()->build_dependencies(rest_moving.context(), build));
}

// Scenes lpi cannot represent are refused before any work, naming what is missing.
TEST(Lpi, RefusesScenesItCannotRepresent) {
  const Scene no_specular = scene_from_yaml(replace_once(kSmallGlassSphere, "{type: glass, ior: 1.5}", "{type: diffuse, albedo: 0.5}"));
  EXPECT_NE(causticbench::testing::input_error_message([&] { causticbench::testing::render(no_specular, "lpi", {}); }).find("has none"), std::string::npos);
  // An environment light with symmetry: test_lpi_environment.cpp.
}

// Beyond the sampled ball: zero gives nothing there, fade never more than clamp, and every value
// is finite; the coarsest and the finest light sets (subdivision 0 and 6) and cells no photon
// reached give finite, non-negative images.
TEST(Lpi, ExtremesAreFiniteAndSane) {
  const Scene scene = scene_from_yaml(kSmallGlassSphere);
  const std::vector<std::string> base = {"photons_per_sample=20000", "grid_resolution=12", "volume_radius=1.6"};
  auto with = [&](std::vector<std::string> extra) {
    extra.insert(extra.end(), base.begin(), base.end());
    return causticbench::testing::render(scene, "lpi", extra);
  };
  const FrameResult clamp = with({"outside=clamp"}), fade = with({"outside=fade"}), zero = with({"outside=zero"});
  const Vec3 center(0.0f, 0.6f, 0.0f);
  const float radius = 1.6f * 0.4f;
  size_t outside = 0;
  for (size_t pixel = 0; pixel < clamp.gbuffer.pixel_count(); ++pixel) {
    const float distance = glm::length(clamp.gbuffer.position[pixel] - center);
    for (int c = 0; c < 3; ++c) {
      ASSERT_TRUE(std::isfinite(clamp.caustic.at(pixel, c)) && std::isfinite(fade.caustic.at(pixel, c)));
      EXPECT_LE(fade.caustic.at(pixel, c), clamp.caustic.at(pixel, c) * (1.0f + 1e-6f));
      if (distance > radius * 1.001f && clamp.gbuffer.receiver[pixel]) {
        EXPECT_EQ(zero.caustic.at(pixel, c), 0.0f);
        outside += c == 0;
      }
      if (distance < radius * 0.999f) {
        EXPECT_EQ(zero.caustic.at(pixel, c), clamp.caustic.at(pixel, c));
      }
    }
  }
  EXPECT_GT(outside, 100u);
  for (const std::string level : {"light_subdivision=0", "light_subdivision=6"}) {
    const FrameResult result = causticbench::testing::render(scene, "lpi", {"light_samples=all", level, "photons_per_sample=40", "grid_resolution=3"});
    for (float value : result.caustic.values()) ASSERT_TRUE(std::isfinite(value) && value >= 0.0f) << level;
  }
}

// The lookup-rate counter: every receiver point reads one light sample (nearest) or three (barycentric,
// aligned) per object and light, or one coefficient stencil (sh); divided by render_ms it is the rate
// of volume reads the Performance section of issue 11 asks for.
TEST(Lpi, CountsTheVolumeReadsOfAFrame) {
  const Scene scene = scene_from_yaml(kSmallGlassSphere);
  auto reads = [&](std::vector<std::string> knobs) {
    knobs.insert(knobs.end(), {"photons_per_sample=200", "grid_resolution=4", "light_subdivision=0"});
    const FrameResult result = causticbench::testing::render(scene, "lpi", knobs, 0);
    double counted = -1.0;
    for (const auto& [name, value] : result.counters)
      if (name == "volume_reads_per_frame") counted = value;
    return std::make_pair(counted, static_cast<double>(result.gbuffer.receiver_count()));
  };
  const auto [nearest, receivers] = reads({"light_samples=all", "blend=nearest"});
  ASSERT_GT(receivers, 0.0);
  EXPECT_EQ(nearest, receivers);
  EXPECT_EQ(reads({"light_samples=all", "blend=barycentric"}).first, 3.0 * receivers);
  EXPECT_EQ(reads({"light_samples=all", "blend=aligned"}).first, 3.0 * receivers);
  EXPECT_EQ(reads({"storage=sh", "sh_order=1"}).first, receivers);
}
