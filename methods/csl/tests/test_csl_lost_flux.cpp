// csl's lost flux (CausticMethod::lost_flux): the caustic rays' energy no spot light carries, against
// what the rendered images show (issue 32).
#include <cstdio>

#include <gtest/gtest.h>

#include "core/image_statistics.h"
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
// energy_coverage 1 nothing is left (exactly 0 here); at 0.5 the first bundle, the ball's refracted
// beam, carries 84 % and the rest is left: the image at 0.5 lacks 8.9 % of the flux it has at 1, less
// than the 16.4 % reported, since most of what is left is Fresnel reflection towards the sky.
// Measured: lost 0.164 and 0; rendered flux ratio 0.911. Bounds: lost above 0.1, the image's shortfall
// at most the reported loss (plus 0.02 for the fits moving light about), and at least a third of it
// (the refracted part of the leftovers does land).
TEST(CslLostFlux, WhatIsLostIsWhatTheImageLacks) {
  const Scene scene = scene_from_yaml(kBall);
  const std::vector<std::string> common = {"rays_per_side=128"};
  std::vector<std::string> half = common, full = common;
  half.push_back("energy_coverage=0.5");
  full.push_back("energy_coverage=1");
  const FrameResult low = render(scene, "csl", half), high = render(scene, "csl", full);
  ASSERT_TRUE(low.lost_flux && high.lost_flux);
  const double flux_ratio = masked_sum(low.caustic, low.gbuffer.receiver) / masked_sum(high.caustic, high.gbuffer.receiver);
  const double carried_ratio = (1.0 - low.lost_flux->fraction) / (1.0 - high.lost_flux->fraction);
  std::printf("energy_coverage 0.5: lost %.4f; 1: lost %.4f; rendered flux ratio %.4f, carried ratio %.4f\n",
              low.lost_flux->fraction, high.lost_flux->fraction, flux_ratio, carried_ratio);
  EXPECT_GT(low.lost_flux->fraction, 0.1);
  EXPECT_EQ(high.lost_flux->fraction, 0.0);
  const double shortfall = 1.0 - flux_ratio, reported = 1.0 - carried_ratio;
  EXPECT_LE(shortfall, reported + 0.02);
  EXPECT_GE(shortfall, reported / 3.0);
  EXPECT_EQ(low.lost_flux->knob, "energy_coverage");
}
