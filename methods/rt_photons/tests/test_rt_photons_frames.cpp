// rt_photons over many frames: adaptive emission converges (its densities stop changing) on a static
// scene and lowers the error at equal photons on the glass sphere's focus; temporal accumulation on a
// static scene converges to the mean of independent frames; on a turning light it lags by alpha / (1 -
// alpha) frames of the caustic's motion, as an exponential average must.
#include <cmath>
#include <cstdio>
#include <memory>

#include <gtest/gtest.h>

#include "core/image_statistics.h"
#include "methods/lifecycle.h"
#include "methods/registry.h"
#include "tests/test_support.h"

namespace causticbench {
namespace {

using causticbench::testing::kSmallGlassSphere;
using causticbench::testing::method_knobs;
using causticbench::testing::render;
using causticbench::testing::scene_from_yaml;

// `count` frames of `scene` (frame f of an animated scene, or frame 0 again and again), one pass.
SequenceOutput play(const Scene& scene, const std::vector<std::string>& knobs, int count, bool animated) {
  std::vector<std::unique_ptr<PosedFrame>> posed;
  std::vector<const PosedFrame*> frames;
  for (int f = 0; f < (animated ? count : 1); ++f) posed.push_back(std::make_unique<PosedFrame>(scene, f));
  for (int f = 0; f < count; ++f) frames.push_back(posed[animated ? f : 0].get());
  std::unique_ptr<CausticMethod> method = create_method("rt_photons");
  const PhaseKnobs phases = method_knobs("rt_photons", knobs);
  return std::move(play_sequence(*method, frames, phases.frame, {phases.render}, TimingProtocol{false, 1}).front());
}

// The caustic's centroid along x (world), weighted by E_c over the receivers.
double centroid_x(const Image& image, const GBuffer& gbuffer) {
  double weighted = 0.0, total = 0.0;
  for (size_t pixel = 0; pixel < gbuffer.pixel_count(); ++pixel) {
    if (!gbuffer.receiver[pixel]) continue;
    weighted += image.at(pixel, 0) * gbuffer.position[pixel].x;
    total += image.at(pixel, 0);
  }
  return weighted / total;
}

double counter(const SequenceOutput& output, const std::string& wanted) {
  for (const auto& [name, value] : output.counters)
    if (name == wanted) return value;
  return 0.0;
}

// Adaptive emission spends its photons where footprints are large and fewer where the sphere focuses; once
// settled it asks for fewer than the budget. The comparison is at equal photons: a uniform map given the
// count the adapted one settled on.
TEST(RtPhotonsFrames, AdaptiveEmissionConvergesAndLowersTheErrorAtEqualPhotons) {
  std::string text = kSmallGlassSphere;
  text.replace(text.find("resolution: [40, 40]"), 20, "resolution: [160, 160]");
  const Scene scene = scene_from_yaml(text);
  const FrameResult reference = render(scene, "reference", causticbench::testing::kSmallSceneReferenceKnobs);
  const std::vector<uint8_t>& receivers = reference.gbuffer.receiver;
  const int frames = 24;
  const SequenceOutput adapted =
      play(scene, {"photons_per_frame=262144", "emission_resolution=32", "adaptive=on", "target_footprint=0.5"}, frames, false);
  const double photons = counter(adapted, "photons_emitted");
  const SequenceOutput uniform = play(
      scene, {"photons_per_frame=" + std::to_string(static_cast<long>(photons)), "emission_resolution=32", "adaptive=off"},
      frames, false);
  const double change = adapted.method_record.at("last_density_change").get<double>();
  double error_on = 0.0, error_off = 0.0;
  for (int f = frames - 4; f < frames; ++f) {
    error_on += relative_mse(adapted.images[f], reference.caustic, receivers) / 4.0;
    error_off += relative_mse(uniform.images[f], reference.caustic, receivers) / 4.0;
  }
  std::printf("adaptive: last density change %.4f, relMSE %.4f with %.0f photons against uniform %.4f with %.0f\n",
              change, error_on, photons, error_off, counter(uniform, "photons_emitted"));
  EXPECT_LT(change, 0.05);
  EXPECT_NEAR(counter(uniform, "photons_emitted"), photons, 0.01 * photons);
  EXPECT_LT(error_on, error_off);
}

TEST(RtPhotonsFrames, TemporalAccumulationOnAStaticSceneConvergesToTheMeanOfIndependentFrames) {
  const Scene scene = scene_from_yaml(kSmallGlassSphere);
  const std::vector<std::string> common = {"photons_per_frame=16384", "emission_resolution=32", "adaptive=off"};
  std::vector<std::string> accumulated = common, single = common;
  accumulated.push_back("temporal_alpha=0.9");
  const int frames = 48;
  const SequenceOutput blended = play(scene, accumulated, frames, false), each = play(scene, single, frames, false);
  const PosedFrame posed(scene, 0);
  Image mean(each.images[0].width(), each.images[0].height(), 3);
  for (const Image& image : each.images)
    for (size_t pixel = 0; pixel < image.pixel_count(); ++pixel)
      mean.set_rgb(pixel, mean.rgb(pixel) + image.rgb(pixel) / static_cast<float>(frames));
  const double single_error = relative_mse(each.images.back(), mean, posed.gbuffer.receiver);
  const double blended_error = relative_mse(blended.images.back(), mean, posed.gbuffer.receiver);
  std::printf("static scene: one frame against the mean of %d: relMSE %.4f; accumulated (alpha 0.9): %.4f\n", frames,
              single_error, blended_error);
  // An exponential average of weight 0.1 keeps (1 - a) / (1 + a) = 1/19 of a frame's variance.
  EXPECT_LT(blended_error, 0.2 * single_error);
  EXPECT_GT(single_error, 0.0);
}

TEST(RtPhotonsFrames, TemporalAccumulationLagsATurningLightByAlphaOverOneMinusAlphaFrames) {
  std::string text = kSmallGlassSphere;
  const std::string sun = "lights: [{type: directional, direction: [0.3, -1, 0.2], irradiance: 1}]";
  text.replace(text.find(sun), sun.size(),
               "frames: 24\nlights: [{type: directional, direction: [0.3, -1, 0.2], irradiance: 1, animation: {keyframes: "
               "[{frame: 0, direction: [0.3, -1, 0.2]}, {frame: 23, direction: [-0.3, -1, 0.2]}]}}]");
  const Scene scene = scene_from_yaml(text);
  const std::vector<std::string> common = {"photons_per_frame=65536", "emission_resolution=32", "adaptive=off"};
  std::vector<std::string> accumulated = common;
  accumulated.push_back("temporal_alpha=0.75");
  const int frames = 24;
  const SequenceOutput blended = play(scene, accumulated, frames, true), each = play(scene, common, frames, true);
  const PosedFrame last(scene, frames - 1), earlier(scene, frames - 9);
  const double velocity = (centroid_x(each.images[frames - 1], last.gbuffer) - centroid_x(each.images[frames - 9], earlier.gbuffer)) / 8.0;
  const double lag = (centroid_x(each.images[frames - 1], last.gbuffer) - centroid_x(blended.images[frames - 1], last.gbuffer)) / velocity;
  std::printf("turning light: the caustic moves %.4f a frame; the accumulated one lags %.2f frames (alpha / (1 - alpha) = 3)\n",
              velocity, lag);
  EXPECT_GT(std::abs(velocity), 0.01);
  EXPECT_NEAR(lag, 3.0, 0.6);
}

}  // namespace
}  // namespace causticbench
