// pinhole's interaction fitted to each object's material (interaction: auto, the default) and the flux it
// reports lost where the interaction does not model an object's material (issue 32).
#include <cstdio>

#include <gtest/gtest.h>

#include "core/image_statistics.h"
#include "tests/test_support.h"

using namespace causticbench;
using causticbench::testing::render;
using causticbench::testing::scene_from_yaml;

namespace {

// A glass ball floating over the left half of the floor and a metal ring on the right, under a sun 39
// degrees from the vertical: the ball's focused spot lands clear of its own silhouette, the ring draws its
// cardioid inside itself, so each half of the floor holds one object's caustic, in view of an
// orthographic camera straight down on the whole floor.
std::string scene_text(bool ball, bool ring) {
  std::string text = R"(
camera: {type: orthographic, position: [0, 5, 0], look_at: [0, 0, 0], up: [0, 0, -1], view_height: 4, resolution: [64, 64]}
lights: [{type: directional, direction: [0.8, -1, 0], irradiance: 1}]
objects:
  - shape: {type: quad, size: [4, 4]}
    material: {type: diffuse, albedo: 0.8}
)";
  if (ball)
    text += R"(  - name: ball
    shape: {type: sphere, radius: 0.35}
    material: {type: glass, ior: 1.5}
    transform: {translate: [-1.3, 0.8, 0]}
)";
  if (ring)
    text += R"(  - name: ring
    shape: {type: ring, radius: 0.6, height: 0.4, thickness: 0.0}
    material: {type: mirror, reflectance: 0.9}
    transform: {translate: [1.1, 0.2, 0]}
)";
  return text;
}

// The caustic flux on the floor's left (x < 0) or right half, relative to the whole image's.
double half_sum(const FrameResult& result, bool left) {
  std::vector<uint8_t> mask(result.gbuffer.pixel_count(), 0);
  for (size_t pixel = 0; pixel < mask.size(); ++pixel)
    mask[pixel] = result.gbuffer.receiver[pixel] && ((result.gbuffer.position[pixel].x < 0.0f) == left);
  return masked_sum(result.caustic, mask);
}

}  // namespace

// At its defaults pinhole refracts at the glass ball and reflects at the ring, in one scene: the ball's
// half of the floor gets its refracted focus (more than half the reference's flux there; one
// interface, so not all of it), where interaction: reflect renders only the ball's Fresnel reflection
// (under 15 %); the ring's half is what reflect gives there (the same samples, within 2 %). The record
// says what each object did.
TEST(PinholeInteraction, AutoRefractsAtGlassAndReflectsAtMirrorsInOneScene) {
  const Scene scene = scene_from_yaml(scene_text(true, true));
  const FrameResult reference = render(scene, "reference", causticbench::testing::kSmallSceneReferenceKnobs);
  const FrameResult automatic = render(scene, "pinhole", {"samples=2000", "filtering=none"});
  const FrameResult reflect = render(scene, "pinhole", {"samples=2000", "filtering=none", "interaction=reflect"});
  const double ball_reference = half_sum(reference, true), ring_reference = half_sum(reference, false);
  std::printf("ball half: auto %.4f, reflect %.4f of the reference; ring half: auto %.4f, reflect %.4f\n",
              half_sum(automatic, true) / ball_reference, half_sum(reflect, true) / ball_reference,
              half_sum(automatic, false) / ring_reference, half_sum(reflect, false) / ring_reference);
  EXPECT_GT(half_sum(automatic, true) / ball_reference, 0.5);
  EXPECT_LT(half_sum(reflect, true) / ball_reference, 0.15);
  EXPECT_NEAR(half_sum(automatic, false) / half_sum(reflect, false), 1.0, 0.02);
  EXPECT_EQ(automatic.method_record["interaction"]["ball"].get<std::string>().rfind("refracts", 0), 0u)
      << automatic.method_record["interaction"].dump();
  EXPECT_EQ(automatic.method_record["interaction"]["ring"].get<std::string>().rfind("reflects", 0), 0u)
      << automatic.method_record["interaction"].dump();
  // The default is the paper's filtered method.
  const FrameResult defaults = render(scene, "pinhole", {"samples=500"});
  EXPECT_EQ(defaults.method_record["filter_implementation"], "own");
}

// Nothing is lost under auto (every object's material is modelled): exactly 0. Under reflect the ball's
// caustic is lost, under refract the ring's: each reported fraction matches the share of the flux that
// the reference gives that object alone (scenes with only the ball, only the ring), within 0.05.
TEST(PinholeInteraction, LostFluxIsTheShareOfTheObjectsItsInteractionDoesNotModel) {
  const Scene both = scene_from_yaml(scene_text(true, true));
  const auto& knobs = causticbench::testing::kSmallSceneReferenceKnobs;
  const double ball_alone = masked_sum(render(scene_from_yaml(scene_text(true, false)), "reference", knobs).caustic,
                                       render(both, "reference", {"max_passes=1", "photons_per_pass=1000"}).gbuffer.receiver);
  const FrameResult ring_reference = render(scene_from_yaml(scene_text(false, true)), "reference", knobs);
  const double ring_alone = masked_sum(ring_reference.caustic, ring_reference.gbuffer.receiver);
  const double ball_share = ball_alone / (ball_alone + ring_alone);
  const FrameResult automatic = render(both, "pinhole", {"samples=500", "filtering=none"});
  const FrameResult reflect = render(both, "pinhole", {"samples=500", "filtering=none", "interaction=reflect"});
  const FrameResult refract = render(both, "pinhole", {"samples=500", "filtering=none", "interaction=refract"});
  ASSERT_TRUE(automatic.lost_flux && reflect.lost_flux && refract.lost_flux);
  std::printf("ball's share %.4f; lost: auto %.4f, reflect %.4f (%s), refract %.4f\n", ball_share,
              automatic.lost_flux->fraction, reflect.lost_flux->fraction, reflect.lost_flux->what.c_str(),
              refract.lost_flux->fraction);
  EXPECT_EQ(automatic.lost_flux->fraction, 0.0);
  EXPECT_NEAR(reflect.lost_flux->fraction, ball_share, 0.05);
  EXPECT_NEAR(refract.lost_flux->fraction, 1.0 - ball_share, 0.05);
  EXPECT_EQ(reflect.lost_flux->knob, "interaction");
}
