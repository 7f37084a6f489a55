// lpi's sampled ball fitted to the scene (volume_radius: auto, methods/lpi/volume_radius.h) and the flux
// it reports lost outside the ball (CausticMethod::lost_flux), against the reference (issue 32).
#include <cmath>
#include <cstdio>

#include <gtest/gtest.h>

#include "core/image_statistics.h"
#include "tests/test_support.h"

using namespace causticbench;
using causticbench::testing::render;
using causticbench::testing::scene_from_yaml;

namespace {

// A glass ball (radius 0.5, on the floor) under a sun 25 degrees above the horizon: its caustic lands
// beyond the ball's shadow, 2 to 4 bounding radii from its centre, partly outside the ball of 3 radii
// that was lpi's fixed default. The orthographic camera looks straight down on the whole 6 m floor, so
// every visible pixel is the same floor area and the reference's sums are flux.
const char* const kLowSun = R"(
camera: {type: orthographic, position: [0, 5, 0], look_at: [0, 0, 0], up: [0, 0, -1], view_height: 6, resolution: [96, 96]}
lights: [{type: directional, direction: [0.9063078, -0.4226183, 0], irradiance: 1}]
objects:
  - shape: {type: quad, size: [6, 6]}
    material: {type: diffuse, albedo: 0.8}
  - name: ball
    shape: {type: sphere, radius: 0.5}
    material: {type: glass, ior: 1.5}
    transform: {translate: [0, 0.5, 0]}
)";

// The fraction of the reference's caustic flux on receivers farther than `radius` from `center`.
double reference_fraction_beyond(const FrameResult& reference, const Vec3& center, float radius) {
  std::vector<uint8_t> beyond(reference.gbuffer.pixel_count(), 0);
  for (size_t pixel = 0; pixel < beyond.size(); ++pixel)
    beyond[pixel] = reference.gbuffer.receiver[pixel] && glm::length(reference.gbuffer.position[pixel] - center) > radius;
  return masked_sum(reference.caustic, beyond) / masked_sum(reference.caustic, reference.gbuffer.receiver);
}

double energy_ratio(const FrameResult& method, const FrameResult& reference) {
  return masked_sum(method.caustic, reference.gbuffer.receiver) / masked_sum(reference.caustic, reference.gbuffer.receiver);
}

}  // namespace

// The low sun: auto chooses a ball that holds the caustic, lpi's energy is the reference's within 5 %
// (vector orientation, grid 64, 200,000 photons) and it reports next to nothing lost. The old fixed
// ball of 3 radii reports as lost the fraction of the reference's flux that lies beyond it, within
// 0.03 (probes: 20,000 photons, a binomial standard error below 0.005; the reference's pixels beyond
// the ball are counted whole). Measured: auto 7.09 radii, energy 0.993, lost 0.0019; at 3 radii lost
// 0.180 against the reference's 0.188 beyond the ball, energy 1.036 (the clamp's surface values). Broken
// on purpose (hits measured in world space, not mapped into build space): 0.157, fails.
TEST(LpiVolumeRadius, AutoHoldsALowSunsCausticAndTheFixedBallReportsWhatItLoses) {
  const Scene scene = scene_from_yaml(kLowSun);
  const FrameResult reference = render(scene, "reference", causticbench::testing::kSmallSceneReferenceKnobs);
  const std::vector<std::string> common = {"orientation=vector", "grid_resolution=64", "photons_per_sample=200000"};

  std::vector<std::string> automatic = common;
  const FrameResult fitted = render(scene, "lpi", automatic);
  const double radii = fitted.method_record["objects"][0]["volume_radius_bounding_radii"].get<double>();
  ASSERT_TRUE(fitted.lost_flux.has_value());
  std::printf("auto: %.3f bounding radii (%s), energy %.4f, lost %.4f\n", radii,
              fitted.method_record["objects"][0]["volume_radius_why"].get<std::string>().c_str(),
              energy_ratio(fitted, reference), fitted.lost_flux->fraction);
  EXPECT_GT(radii, 3.0) << "the caustic reaches beyond the old default";
  EXPECT_LT(fitted.lost_flux->fraction, 0.01);
  EXPECT_NEAR(energy_ratio(fitted, reference), 1.0, 0.05);

  std::vector<std::string> fixed = common;
  fixed.push_back("volume_radius=3");
  const FrameResult old = render(scene, "lpi", fixed);
  ASSERT_TRUE(old.lost_flux.has_value());
  // The bounding sphere of a sphere is itself: centre (0, 0.5, 0), radius 0.5.
  const double outside = reference_fraction_beyond(reference, Vec3(0.0f, 0.5f, 0.0f), 1.5f);
  std::printf("volume_radius 3: lost %.4f, the reference's flux beyond the ball %.4f, energy %.4f (%s)\n",
              old.lost_flux->fraction, outside, energy_ratio(old, reference), old.lost_flux->advice.c_str());
  EXPECT_GT(outside, 0.1) << "the case must lose enough to measure";
  EXPECT_NEAR(old.lost_flux->fraction, outside, 0.03);
  EXPECT_EQ(old.lost_flux->knob, "volume_radius");
}

// Nothing is lost where nothing can land outside: a 2 m floor whose farthest point lies within 3.1
// radii of the ball's centre reads exactly 0 at volume_radius 3.1.
TEST(LpiVolumeRadius, NothingLostWhenEveryReceiverLiesInsideTheBall) {
  const Scene scene = scene_from_yaml(R"(
camera: {type: orthographic, position: [0, 5, 0], look_at: [0, 0, 0], up: [0, 0, -1], view_height: 2, resolution: [24, 24]}
lights: [{type: directional, direction: [0.3, -1, 0.2], irradiance: 1}]
objects:
  - shape: {type: quad, size: [2, 2]}
    material: {type: diffuse, albedo: 0.8}
  - shape: {type: sphere, radius: 0.5}
    material: {type: glass, ior: 1.5}
    transform: {translate: [0, 0.5, 0]}
)");
  const FrameResult lpi = render(scene, "lpi", {"grid_resolution=16", "photons_per_sample=20000", "volume_radius=3.1"});
  ASSERT_TRUE(lpi.lost_flux.has_value());
  EXPECT_EQ(lpi.lost_flux->fraction, 0.0);
}

// `render` warns about a run that loses more than 5 %, naming the knob and what to set; at auto it does
// not (the same low sun, fewer photons: the count does not depend on them).
TEST(LpiVolumeRadius, RenderWarnsAboutWhatAFixedBallLosesAndNamesTheKnob) {
  causticbench::testing::TemporaryFolder folder("lpi_volume_radius_warning");
  const std::string scene = folder.write("low_sun.yaml", kLowSun);
  std::string output;
  const std::string render = std::string(CAUSTICBENCH_BINARY) + " -q render " + scene +
                             " --method lpi --set photons_per_sample=20000 --set grid_resolution=64 --out " +
                             folder.path("out");
  ASSERT_EQ(causticbench::testing::run_command(render + " --set volume_radius=3", output), 0) << output;
  EXPECT_NE(output.find("warning: lpi loses 18."), std::string::npos) << output;
  EXPECT_NE(output.find("set volume_radius: auto"), std::string::npos) << output;
  ASSERT_EQ(causticbench::testing::run_command(render, output), 0) << output;
  EXPECT_EQ(output.find("loses"), std::string::npos) << output;
}
