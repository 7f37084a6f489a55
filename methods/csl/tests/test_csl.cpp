// csl (Liu 2008) as a method: against the reference on the glass sphere, the scenes it refuses,
// objects without caustic rays, the intensity correction of Fig. 6. Its closed forms and fitting
// stages: test_csl_math.cpp; the interface checks every method shares: test_conformance.cpp.
#include <cmath>

#include <gtest/gtest.h>

#include "core/errors.h"
#include "core/image_statistics.h"
#include "methods/lifecycle.h"
#include "methods/registry.h"
#include "tests/test_support.h"

using namespace causticbench;
using causticbench::testing::input_error_message;
using causticbench::testing::kSmallGlassSphere;
using causticbench::testing::replace_once;
using causticbench::testing::scene_from_yaml;

namespace {

// Receivers farther than `radius` from the reference's brightest receiver: away from the focus,
// where a caustic's peak value depends on how finely it is resolved more than on the method.
std::vector<uint8_t> away_from_focus(const FrameResult& reference, float radius) {
  size_t brightest = 0;
  for (size_t pixel = 0; pixel < reference.gbuffer.pixel_count(); ++pixel) {
    if (reference.gbuffer.receiver[pixel] && reference.caustic.at(pixel, 1) > reference.caustic.at(brightest, 1)) {
      brightest = pixel;
    }
  }
  std::vector<uint8_t> mask(reference.gbuffer.pixel_count(), 0);
  for (size_t pixel = 0; pixel < mask.size(); ++pixel) {
    mask[pixel] = reference.gbuffer.receiver[pixel] &&
                  glm::length(reference.gbuffer.position[pixel] - reference.gbuffer.position[brightest]) > radius;
  }
  return mask;
}

std::vector<uint8_t> receivers(const FrameResult& result) { return result.gbuffer.receiver; }

}  // namespace

// The glass sphere under a directional light: a few spot lights cover it, and its E_c agrees with
// the reference's away from the focus and in total. Measured (256 rays a side, reference 6 x
// 200,000 photons): 5 spot lights covering 0.969 of the rays' energy, relMSE 0.1634 away from the
// focus, energy ratio 0.9876 (without the intensity correction relMSE 0.424). Bounds 1.5 times the
// deviations (issue 51); coverage is the energy_coverage default's, 0.95.
TEST(Csl, GlassSphereMatchesTheReference) {
  const Scene scene = scene_from_yaml(replace_once(kSmallGlassSphere, "resolution: [40, 40]", "resolution: [64, 64]"));
  const FrameResult reference = causticbench::testing::render(scene, "reference", causticbench::testing::kSmallSceneReferenceKnobs);
  const FrameResult csl = causticbench::testing::render(scene, "csl", {"rays_per_side=256"});
  const nlohmann::json& set = csl.method_record["objects"][0]["sets"][0];
  EXPECT_EQ(csl.method_record["objects"][0]["light_sample_set"], "static");
  const std::vector<uint8_t> away = away_from_focus(reference, 0.1f);
  const double relmse = relative_mse(csl.caustic, reference.caustic, away);
  const double energy = masked_sum(csl.caustic, receivers(csl)) / masked_sum(reference.caustic, receivers(reference));
  std::printf("glass sphere: %d spot lights, coverage %.3f, relMSE away from the focus %.4f, energy ratio %.4f\n",
              set["spot_lights"].get<int>(), set["coverage"].get<double>(), relmse, energy);
  EXPECT_LE(set["spot_lights"].get<int>(), 8);
  EXPECT_GE(set["coverage"].get<double>(), 0.95);
  EXPECT_LT(relmse, 1.5 * 0.1634);
  EXPECT_NEAR(energy, 1.0, 1.5 * 0.0124);
  // Fig. 6: without the intensity correction of Eq. 4 the focusing is lost.
  const FrameResult uncorrected =
      causticbench::testing::render(scene, "csl", {"rays_per_side=256", "intensity_correction=off"});
  const double uncorrected_relmse = relative_mse(uncorrected.caustic, reference.caustic, away);
  std::printf("glass sphere without the intensity correction: relMSE away from the focus %.4f\n", uncorrected_relmse);
  EXPECT_GT(uncorrected_relmse, 2.0 * relmse);
}

// Scenes csl cannot represent are refused before any ray is traced, naming what is wrong.
TEST(Csl, RefusesScenesItCannotRepresent) {
  const Scene no_specular = scene_from_yaml(replace_once(kSmallGlassSphere, "material: {type: glass, ior: 1.5}",
                                                         "material: {type: diffuse, albedo: 0.5}"));
  EXPECT_NE(input_error_message([&] { causticbench::testing::render(no_specular, "csl", {"rays_per_side=8"}); })
                .find("has none"),
            std::string::npos);
  const Scene environment = scene_from_yaml(replace_once(
      kSmallGlassSphere, "lights: [{type: directional, direction: [0.3, -1, 0.2], irradiance: 1}]",
      "lights: [{type: environment, procedural: gaussian_spot, direction: [0.3, -1, 0.2], irradiance: 1, solid_angle_sr: 0.1}]"));
  EXPECT_NE(input_error_message([&] { causticbench::testing::render(environment, "csl", {"rays_per_side=8"}); })
                .find("environment light"),
            std::string::npos);
}

// An object that sends no light on (a black mirror) makes no spot light and no caustic, and stays finite.
TEST(Csl, AnObjectWithoutCausticRaysGivesNothing) {
  const Scene black = scene_from_yaml(
      replace_once(kSmallGlassSphere, "material: {type: glass, ior: 1.5}", "material: {type: mirror, reflectance: 0}"));
  const FrameResult csl = causticbench::testing::render(black, "csl", {"rays_per_side=32"});
  EXPECT_EQ(csl.method_record["objects"][0]["sets"][0]["spot_lights"], 0);
  EXPECT_EQ(masked_sum(csl.caustic, csl.gbuffer.receiver), 0.0);
}

// Model only what the scene requires: one rendered frame of an animated light is a static light (two
// that turn it build the dynamic sets of Section 4: test_csl_dynamic.cpp).
TEST(Csl, ModelsOnlyTheLightDirectionsTheFramesNeed) {
  const std::string animated = replace_once(
      kSmallGlassSphere, "direction: [0.3, -1, 0.2], irradiance: 1",
      "direction: [0.3, -1, 0.2], irradiance: 1, animation: {keyframes: [{frame: 0, direction: [0.3, -1, 0.2]}, {frame: 1, direction: [-0.4, -1, 0]}]}");
  const Scene moving = scene_from_yaml("frames: 2\n" + animated);
  const FrameResult one = causticbench::testing::render(moving, "csl", {"rays_per_side=16"}, 1);
  EXPECT_EQ(one.method_record["objects"][0]["light_sample_set"], "static");
  EXPECT_EQ(one.method_record["objects"][0]["sets"].size(), 1u);
}

// An object moved by its animation carries its spot lights along: frame 1 renders as the same object
// standing at frame 1's place does.
TEST(Csl, TheCausticMovesWithItsObject) {
  const std::string still = replace_once(kSmallGlassSphere, "translate: [0, 0.6, 0]", "translate: [0.2, 0.6, -0.1]");
  const std::string moving = "frames: 2\n" + replace_once(kSmallGlassSphere, "transform: {translate: [0, 0.6, 0]}",
                                                          "animation: {keyframes: [{frame: 0, translate: [0, 0.6, 0]}, "
                                                          "{frame: 1, translate: [0.2, 0.6, -0.1]}]}");
  const FrameResult a = causticbench::testing::render(scene_from_yaml(still), "csl", {"rays_per_side=64"});
  const FrameResult b = causticbench::testing::render(scene_from_yaml(moving), "csl", {"rays_per_side=64"}, 1);
  double largest = 0.0, difference = 0.0;
  for (size_t i = 0; i < a.caustic.values().size(); ++i) {
    largest = std::max(largest, static_cast<double>(a.caustic.values()[i]));
    difference = std::max(difference, std::fabs(static_cast<double>(a.caustic.values()[i]) - b.caustic.values()[i]));
  }
  ASSERT_GT(largest, 0.0);
  EXPECT_LT(difference, 1e-4 * largest);
}

// occlusion: shadow_rays (beyond the paper): a thin diffuse wall beside the glass sphere's caustic
// casts a caustic shadow on the floor. Without shadow rays the caustic shines through it; with them
// the error on the floor agrees with the reference. Measured (64x64, 256 rays a side): without,
// energy 1.086 and relMSE 3.78; with, energy 1.033 and relMSE 0.112.
TEST(Csl, ShadowRaysCastTheCausticShadowOfAnOccluder) {
  const Scene scene = scene_from_yaml(
      replace_once(kSmallGlassSphere, "resolution: [40, 40]", "resolution: [64, 64]") +
      "  - shape: {type: box, size: [0.02, 0.3, 1.2]}\n    material: {type: diffuse, albedo: 0.5}\n"
      "    transform: {translate: [0.3, 0.15, 0]}\n");
  const FrameResult reference = causticbench::testing::render(scene, "reference", causticbench::testing::kSmallSceneReferenceKnobs);
  const FrameResult through = causticbench::testing::render(scene, "csl", {"rays_per_side=256"});
  const FrameResult shadowed = causticbench::testing::render(scene, "csl", {"rays_per_side=256", "occlusion=shadow_rays"});
  // The floor only: the wall's sides rise between the sphere and some spot lights' light planes, where
  // a spot light has no rays (a limit of the representation, not of the shadow rays).
  std::vector<uint8_t> mask = reference.gbuffer.receiver;
  for (size_t pixel = 0; pixel < mask.size(); ++pixel) mask[pixel] = mask[pixel] && reference.gbuffer.position[pixel].y < 0.05f;
  const double flux = masked_sum(reference.caustic, mask);
  ASSERT_GT(flux, 0.0);
  const double through_energy = masked_sum(through.caustic, mask) / flux, shadowed_energy = masked_sum(shadowed.caustic, mask) / flux;
  const double through_relmse = relative_mse(through.caustic, reference.caustic, mask);
  const double shadowed_relmse = relative_mse(shadowed.caustic, reference.caustic, mask);
  std::printf("occluder: without shadow rays energy %.4f relMSE %.4f; with shadow rays energy %.4f relMSE %.4f\n",
              through_energy, through_relmse, shadowed_energy, shadowed_relmse);
  EXPECT_NEAR(shadowed_energy, 1.0, 0.1);
  EXPECT_GT(through_energy - shadowed_energy, 0.025);
  EXPECT_LT(shadowed_relmse, 0.1 * through_relmse);
}

// Section 3.1.1 on a complex object: the glass bunny under the sun of configs/scenes/bunny.yaml is
// covered to the paper's 95 % by about as many spot lights as its Table 2 reports (8.50 per direction),
// and its bundles' axes settle as the paper says they usually do ("about 15 iterations"). With a
// distance threshold of 0.1 bounding radii (the default before) each bundle was a thin slice of one
// converging field: 34 spot lights at 128 rays a side, 32 of them stopped by the 100-step cap.
// Measured at 0.3: 8 spot lights, coverage 0.970, iterations 8 to 21 but one at the cap.
TEST(Csl, TheBunnyNeedsAboutThePapersSpotLightsPerDirection) {
  const Scene bunny = scene_from_yaml(R"(
camera: {position: [2.4, 1.7, 1.6], look_at: [0.25, 0.25, 0.0], fov_degrees: 36, resolution: [16, 16]}
lights: [{type: directional, direction: [0.5735764, -0.8191520, 0.0], irradiance: 3}]
objects:
  - shape: {type: quad, size: [10, 10]}
    material: {type: diffuse, albedo: 0.75}
  - shape: {type: mesh, asset: bunny, smooth_normals: true, fit_size: 1.0}
    transform: {translate: [0.0, 0.002, 0.0], rotate: [0.0, 270.0, 0.0]}
    material: {type: glass, ior: 1.5}
)");
  const FrameResult csl = causticbench::testing::render(bunny, "csl", {"rays_per_side=128"});
  const nlohmann::json& set = csl.method_record["objects"][0]["sets"][0];
  int converged = 0;
  for (const nlohmann::json& light : set["lights"]) converged += light["bundle_converged"].get<bool>() ? 1 : 0;
  std::printf("bunny: %d spot lights, coverage %.3f, %d bundles converged before the cap\n", set["spot_lights"].get<int>(),
              set["coverage"].get<double>(), converged);
  EXPECT_GE(set["coverage"].get<double>(), 0.95);
  EXPECT_LE(set["spot_lights"].get<int>(), 12);
  EXPECT_GE(2 * converged, set["spot_lights"].get<int>()) << "most bundles converge";
}

// Issue 30, defect 5: with min_energy 0, branches of vanishing energy reach the fit; their zero weight made
// the derivative of sqrt(w x) 0 / 0, Ceres failed three of five fits at their first evaluation, kept the
// unfitted guess unnoticed and wrote about 100 lines of its log to stderr. Every fit now succeeds, a failed
// one would be recorded (fit_failed), and nothing of Ceres reaches the terminal.
TEST(Csl, ZeroMinimumEnergyFitsEverySpotLightQuietly) {
  const causticbench::testing::TemporaryFolder folder("csl_min_energy");
  const std::string scene = folder.write("scene.yaml", kSmallGlassSphere);
  std::string output;
  int code = causticbench::testing::run_command(std::string(CAUSTICBENCH_BINARY) + " -q render " + scene +
                                                    " --method csl --set min_energy=0 --set rays_per_side=128 --out " +
                                                    folder.path("out"),
                                                output);
  ASSERT_EQ(code, 0) << output;
  EXPECT_EQ(output.find("ResidualBlock"), std::string::npos) << output;
  EXPECT_EQ(output.find("Terminating"), std::string::npos) << output;
  nlohmann::json record = nlohmann::json::parse(causticbench::testing::read_whole_file(folder.path("out/record.json")));
  int fits = 0;
  for (const nlohmann::json& object : record["method_record"]["objects"])
    for (const nlohmann::json& set : object["sets"])
      for (const nlohmann::json& light : set["lights"]) {
        ++fits;
        EXPECT_FALSE(light["fit_failed"].get<bool>());
        EXPECT_GT(light["fit_iterations"].get<int>(), 0);
      }
  EXPECT_GE(fits, 3);
}
