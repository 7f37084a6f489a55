// csl's lost flux (CausticMethod::lost_flux): the caustic rays' energy no spot light carries, against
// what the rendered images show (issue 32).
#include <cstdio>

#include <gtest/gtest.h>

#include "core/image_statistics.h"
#include "experiments/light_account.h"
#include "methods/registry.h"
#include "tests/test_support.h"

using namespace causticbench;
using causticbench::testing::render;
using causticbench::testing::scene_from_yaml;

namespace {

// A glass ball over a floor the orthographic camera sees whole, under a near-vertical sun: the ball's
// refracted light lands on the floor in view.
const char* const kBall = R"(
camera: {type: orthographic, position: [0, 5, 0], look_at: [0, 0, 0], up: [0, 0, -1], view_height: 4, resolution: [64, 64]}
lights: [{type: directional, direction: [0.2, -1, 0.1], irradiance: 1}]
objects:
  - shape: {type: quad, size: [4, 4]}
    material: {type: diffuse, albedo: 0.8}
  - shape: {type: sphere, radius: 0.4}
    material: {type: glass, ior: 1.5}
    transform: {translate: [0, 1.2, 0]}
)";

}  // namespace

// csl counts the energy of the object rays no spot light carries, whether or not a ray would reach a
// receiver (they are traced through the object alone): what its image lacks is at most that. At
// energy_coverage 1 nothing is left uncovered (exactly 0 here); at 0.5 the first bundle, the ball's
// refracted beam, carries 84 % and the rest is left: the image at 0.5 lacks 8.9 % of the flux it has at
// 1, less than the 16.4 % reported, since most of what is left is Fresnel reflection towards the sky.
// Its lost flux also counts the light its spot lights move (LostFlux::moved, kMisdirectedChord), which
// this test leaves out: the uncovered part is fraction - moved. Measured: uncovered 0.164 and 0; rendered
// flux ratio 0.911. Bounds: uncovered above 0.1, the image's shortfall at most the reported loss (plus
// 0.02 for the fits moving light about), and at least a third of it (the refracted part of the leftovers
// does land).
TEST(CslLostFlux, WhatIsLostIsWhatTheImageLacks) {
  const Scene scene = scene_from_yaml(kBall);
  const std::vector<std::string> common = {"rays_per_side=128"};
  std::vector<std::string> half = common, full = common;
  half.push_back("energy_coverage=0.5");
  full.push_back("energy_coverage=1");
  const FrameResult low = render(scene, "csl", half), high = render(scene, "csl", full);
  ASSERT_TRUE(low.lost_flux && high.lost_flux);
  const double low_uncovered = low.lost_flux->fraction - low.lost_flux->moved;
  const double high_uncovered = high.lost_flux->fraction - high.lost_flux->moved;
  const double flux_ratio = masked_sum(low.caustic, low.gbuffer.receiver) / masked_sum(high.caustic, high.gbuffer.receiver);
  const double carried_ratio = (1.0 - low_uncovered) / (1.0 - high_uncovered);
  std::printf("energy_coverage 0.5: uncovered %.4f (moved %.4f); 1: uncovered %.4f (moved %.4f); rendered flux ratio "
              "%.4f, carried ratio %.4f\n",
              low_uncovered, low.lost_flux->moved, high_uncovered, high.lost_flux->moved, flux_ratio, carried_ratio);
  EXPECT_GT(low_uncovered, 0.1);
  EXPECT_DOUBLE_EQ(high_uncovered, 0.0);
  const double shortfall = 1.0 - flux_ratio, reported = 1.0 - carried_ratio;
  EXPECT_LE(shortfall, reported + 0.02);
  EXPECT_GE(shortfall, reported / 3.0);
  EXPECT_EQ(low.lost_flux->knob, "energy_coverage");
}

// A glass torus under a sun focuses its light on a ring, which a spot light's point focus (every ray aimed
// at one axis, f(r) = alpha / (1 + beta r)) cannot hold: the fit's compromise moves the ring inwards, under
// the torus, out of the camera's sight (issue 52: energy 0.24 of the reference's in view while 4.4 % of the
// rays went uncovered). That light is counted as moved (the rays a spot light carries more than
// kMisdirectedChord off their own direction), so the light account closes: the energy lies within what the
// lost flux and csl's declarations (no reflection, no multiple bounces) account for, to the account's
// tolerance. The advice it gives, a lower angle_threshold (bundles of rays closer in direction), lowers the
// lost flux. Measured at 128 x 128, rays_per_side 512: lost 0.66 (of it moved 0.62) at angle_threshold 90,
// 0.52 at 30; energy 0.21 against a lower bound of 0.26.
TEST(CslLostFlux, ATorussRingFocusIsMovedLightAndTheAdviceRecoversSome) {
  const Scene torus = scene_from_yaml(R"(
camera: {position: [0, 3.2, 2.4], look_at: [0, 0, 0], fov_degrees: 40, resolution: [128, 128]}
lights: [{type: directional, direction: [0.5, -0.8660254, 0], irradiance: 3}]
objects:
  - shape: {type: quad, size: [10, 10]}
    material: {type: diffuse, albedo: 0.75}
  - shape: {type: torus, major_radius: 0.5, minor_radius: 0.2}
    material: {type: glass, ior: 1.5}
    transform: {translate: [0, 0.45, 0]}
)");
  const FrameResult reference = render(torus, "reference", {"photons_per_pass=250000", "max_passes=4", "min_passes=4",
                                                             "target_error=0", "max_seconds=0"});
  const FrameResult wide = render(torus, "csl", {"rays_per_side=512"});
  const FrameResult narrow = render(torus, "csl", {"rays_per_side=512", "angle_threshold=30"});
  ASSERT_TRUE(wide.lost_flux && narrow.lost_flux);
  const std::vector<uint8_t>& mask = reference.gbuffer.receiver;
  const double energy = masked_sum(wide.caustic, mask) / masked_sum(reference.caustic, mask);
  const std::optional<LightAccount> account = account_for_light(reference.method_record, find_method("csl").info().capabilities,
                                                                energy, wide.lost_flux->fraction, wide.lost_flux->moved);
  ASSERT_TRUE(account);
  std::printf("torus: csl energy %.3f, lost %.3f (moved %.3f); angle_threshold 30: lost %.3f; %s\n", energy,
              wide.lost_flux->fraction, wide.lost_flux->moved, narrow.lost_flux->fraction,
              describe_light_account(*account).c_str());
  EXPECT_GT(wide.lost_flux->moved, 0.5);
  EXPECT_FALSE(account->flagged) << describe_light_account(*account);
  EXPECT_EQ(wide.lost_flux->knob, "angle_threshold");
  EXPECT_LT(narrow.lost_flux->fraction, wide.lost_flux->fraction - 0.05);
}
