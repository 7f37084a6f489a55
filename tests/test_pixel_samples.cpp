// The harness's pixel_samples (docs/metrics.md): a method rendered at a stratified grid of points in
// each pixel and averaged, points that see no receiver counting zero; its run key and its refusals.
#include <fstream>

#include <gtest/gtest.h>

#include "core/image_statistics.h"
#include "experiments/experiment.h"
#include "methods/lifecycle.h"
#include "tests/test_support.h"

using namespace causticbench;
using causticbench::testing::scene_from_yaml;

namespace {

// A method whose E_c is a step in x at every G-buffer point: 1 W/m^2 where x > 0, 0 elsewhere. Its pixel
// average is the fraction of the pixel's receiver area beyond x = 0, which the test knows exactly.
class StepMethod : public CausticMethod {
 public:
  const MethodInfo& info() const override {
    static const MethodInfo info = [] {
      MethodInfo m;
      m.name = "step";
      return m;
    }();
    return info;
  }
  void prepare(const PrepareContext&, const ParamSet&) override {}
  void update(const FrameContext&, const ParamSet&) override {}
  Image render(const GBuffer& gbuffer, const ParamSet&) override {
    ++renders;
    Image image(gbuffer.width, gbuffer.height, 3);
    for (size_t pixel = 0; pixel < gbuffer.pixel_count(); ++pixel)
      image.set_rgb(pixel, Color(gbuffer.position[pixel].x > 0.0f ? 1.0f : 0.0f));
    return image;
  }
  size_t memory_bytes() const override { return 0; }
  Counters counters() const override { return {}; }
  int renders = 0;
};

// An orthographic camera straight down on a diffuse floor, 8 x 8 pixels of 0.25, centred on x = CX: with
// CX = 0 the step at x = 0 runs along pixel edges; with CX = 0.125 through the middle of a column.
std::string floor_scene(const std::string& centre_x, const std::string& extra = "") {
  return "camera: {type: orthographic, position: [" + centre_x + ", 5, 0], look_at: [" + centre_x +
         ", 0, 0], up: [0, 0, -1], view_height: 2, resolution: [8, 8]}\n"
         "lights: [{type: directional, direction: [0, -1, 0], irradiance: 1}]\n"
         "objects:\n"
         "  - shape: {type: quad, size: [8, 8]}\n"
         "    material: {type: diffuse}\n" +
         extra;
}

Image play(const Scene& scene, StepMethod& method, int samples) {
  PosedFrame posed(scene, 0);
  return play_sequence(method, {&posed}, ParamSet(), {ParamSet()}, TimingProtocol{false, 1, samples}).front().images.front();
}

}  // namespace

// The 4 x 4 grid's points sit at 1/8, 3/8, 5/8 and 7/8 of a pixel: a pixel the step crosses in its
// middle reads exactly one half; one it does not cross reads what its centre reads.
TEST(PixelSamples, AverageTheStratifiedPointsOfEachPixel) {
  StepMethod method;
  Scene on_edges = scene_from_yaml(floor_scene("0"));
  Image centre = play(on_edges, method, 1);
  EXPECT_EQ(method.renders, 1);
  Image sixteen = play(on_edges, method, 16);
  EXPECT_EQ(method.renders, 1 + 16) << "one render per sub-pixel";
  EXPECT_EQ(sixteen.values(), centre.values()) << "the step runs along pixel edges: no pixel is crossed";
  EXPECT_GT(masked_sum(sixteen, PosedFrame(on_edges, 0).gbuffer.receiver), 0.0);

  Scene crossing = scene_from_yaml(floor_scene("0.125"));
  Image halves = play(crossing, method, 16);
  PosedFrame posed(crossing, 0);
  int crossed = 0;
  for (size_t pixel = 0; pixel < 64; ++pixel) {
    ASSERT_TRUE(posed.gbuffer.receiver[pixel]);
    float x = posed.gbuffer.position[pixel].x;
    if (std::abs(x) < 1e-4f) {
      ++crossed;
      EXPECT_FLOAT_EQ(halves.at(pixel, 0), 0.5f) << "pixel " << pixel;
    } else {
      EXPECT_FLOAT_EQ(halves.at(pixel, 0), x > 0.0f ? 1.0f : 0.0f) << "pixel " << pixel;
    }
  }
  EXPECT_EQ(crossed, 8) << "one column of pixels is centred on the step";
}

// Sub-pixel points that see no receiver (a mirror disk above the floor) count zero: a pixel partly
// covered reads the fraction of its 16 points that see the floor beyond the step.
TEST(PixelSamples, PointsOnNoReceiverCountZero) {
  Scene scene = scene_from_yaml(floor_scene("0", "  - shape: {type: disk, radius: 0.3}\n    material: {type: mirror}\n"
                                                 "    transform: {translate: [0.5, 0.1, 0]}\n"));
  StepMethod method;
  Image image = play(scene, method, 16);
  PosedFrame posed(scene, 0);
  std::vector<GBuffer> points;
  posed.for_each_subpixel_gbuffer(16, [&](const GBuffer& buffer) { points.push_back(buffer); });
  ASSERT_EQ(points.size(), 16u);
  int partial = 0;
  for (size_t pixel = 0; pixel < 64; ++pixel) {
    if (!posed.gbuffer.receiver[pixel]) continue;
    int seen = 0;
    for (const GBuffer& buffer : points) seen += buffer.receiver[pixel] && buffer.position[pixel].x > 0.0f ? 1 : 0;
    EXPECT_FLOAT_EQ(image.at(pixel, 0), seen / 16.0f) << "pixel " << pixel;
    if (posed.gbuffer.position[pixel].x > 0.0f && seen < 16) ++partial;
  }
  EXPECT_GT(partial, 0) << "some receiver pixel is partly covered by the disk";
}

TEST(PixelSamples, KeyedOnlyWhenNotOneAndRefusedWhenNotASquare) {
  const causticbench::testing::TemporaryFolder folder("pixel_samples_test");
  auto load = [&](const std::string& line) {
    std::string text =
        causticbench::testing::read_whole_file(std::string(CAUSTICBENCH_SCENES) + "/../experiments/quickstart.yaml");
    text = causticbench::testing::replace_once(text, "scene: ../scenes/ring.yaml",
                                               "scene: " + std::string(CAUSTICBENCH_SCENES) + "/ring.yaml");
    text = causticbench::testing::replace_once(text, "repetitions: 3", "repetitions: 3\n" + line);
    std::ofstream(folder.path("quickstart.yaml")) << text;
    return load_experiment(folder.path("quickstart.yaml"));
  };
  Experiment one = load(""), explicit_one = load("pixel_samples: 1"), four = load("pixel_samples: 4");
  ASSERT_EQ(one.runs.size(), four.runs.size());
  for (size_t r = 0; r < one.runs.size(); ++r) {
    EXPECT_EQ(one.runs[r].key, explicit_one.runs[r].key);
    EXPECT_NE(one.runs[r].key, four.runs[r].key);
  }
  EXPECT_EQ(four.pixel_samples, 4);
  std::string message = causticbench::testing::input_error_message([&] { load("pixel_samples: 5"); });
  EXPECT_NE(message.find("pixel_samples"), std::string::npos) << message;
  EXPECT_NE(message.find("square"), std::string::npos) << message;
}
