// csl's Vulkan backend (backend: vulkan, methods/csl/csl.comp) against its CPU backend: the same
// prepared spot lights evaluated by both, for a static light and for a dynamic light's interpolated
// frame, with each evaluation knob; the dump -> causticbench-gpubench -> gpu-compare round trip; and
// the refusal of shadow rays on the device. Skipped, saying why, where no Vulkan device exists.
#include <filesystem>
#include <fstream>
#include <sstream>

#include <gtest/gtest.h>

#include "core/image_statistics.h"
#include "gpu/vulkan_context.h"
#include "methods/csl/frame_data.h"
#include "methods/frame_dump.h"
#include "methods/lifecycle.h"
#include "methods/registry.h"
#include "tests/test_support.h"

using namespace causticbench;
using causticbench::testing::kSmallGlassSphere;
using causticbench::testing::replace_once;
using causticbench::testing::scene_from_yaml;

namespace {

#define SKIP_WITHOUT_VULKAN() CAUSTICBENCH_SKIP_WITHOUT_VULKAN("csl's backend: vulkan")

PhaseKnobs csl_knobs(const std::vector<std::string>& knobs) { return causticbench::testing::method_knobs("csl", knobs); }

// The agreement bounds of csl's dump format (methods/csl/frame_replay.cpp), which gpu-compare applies:
// relMSE over the receivers and the ratio of total flux. Their reason: docs/gpu.md, "The csl format".
struct Agreement {
  double relmse, flux;
};
Agreement agreement(const Image& vulkan, const Image& cpu, const std::vector<uint8_t>& receivers) {
  const double cpu_flux = masked_sum(cpu, receivers);
  EXPECT_GT(cpu_flux, 0.0);
  return {relative_mse(vulkan, cpu, receivers), masked_sum(vulkan, receivers) / cpu_flux - 1.0};
}

const FrameDumpFormat& csl_format() { return frame_dump_format("csl"); }

// One prepared and updated instance renders each render knob set on both backends.
void expect_backends_agree(CausticMethod& method, const PosedFrame& frame, const std::vector<std::vector<std::string>>& sets,
                           const std::string& what) {
  for (const std::vector<std::string>& set : sets) {
    std::vector<std::string> vulkan_set = set;
    vulkan_set.push_back("backend=vulkan");
    const Image cpu = method.render(frame.gbuffer, csl_knobs(set).render);
    const Image vulkan = method.render(frame.gbuffer, csl_knobs(vulkan_set).render);
    ASSERT_NE(method.gpu(), nullptr);
    ASSERT_TRUE(method.gpu()->gpu_render_milliseconds().has_value());
    EXPECT_FALSE(method.record()["gpu_device"].get<std::string>().empty());
    const Agreement measured = agreement(vulkan, cpu, frame.gbuffer.receiver);
    std::string knobs;
    for (const std::string& knob : set) knobs += " " + knob;
    std::printf("%s%s: vulkan against cpu relMSE %.3g, flux %+.3g\n", what.c_str(), knobs.c_str(), measured.relmse,
                measured.flux);
    EXPECT_LT(measured.relmse, csl_format().relmse_tolerance) << what << knobs;
    EXPECT_LT(std::abs(measured.flux), csl_format().flux_tolerance) << what << knobs;
  }
}

// The render knob sets compared: Eq. 4 on and off, and both on-axis treatments (the paper's epsilon
// wide enough, 0.05 bounding radii, that points near the axis move out to it).
const std::vector<std::vector<std::string>> kEvaluationKnobs = {
    {}, {"intensity_correction=off"}, {"on_axis=epsilon", "axis_epsilon=0.05"}, {"on_axis=epsilon", "intensity_correction=off"}};

}  // namespace

// A static light on the glass sphere, with uint16 images (the default, decoded as the CPU decodes them)
// and float32 ones.
TEST(CslVulkan, AgreesWithTheCpuOnTheGlassSphere) {
  SKIP_WITHOUT_VULKAN();
  const Scene scene = scene_from_yaml(kSmallGlassSphere);
  const MethodEntry& entry = find_method("csl");
  for (const char* precision : {"precision=uint16", "precision=float32"}) {
    const PhaseKnobs knobs = csl_knobs({"rays_per_side=96", "image_size=128", precision});
    std::unique_ptr<CausticMethod> method = entry.create();
    const RestPose rest(scene, {0});
    prepare_method(*method, rest.context(), knobs.build);
    ASSERT_EQ(method->record()["objects"][0]["light_sample_set"], "static");
    const PosedFrame frame(scene, 0);
    method->update(frame.context(), knobs.frame);
    expect_backends_agree(*method, frame, kEvaluationKnobs, std::string("glass sphere, ") + precision);
  }
}

// A dynamic light: frame 1's direction lies on no precomputed one, so its spot lights are the CPU's
// interpolation of triples, whose images the kernel blends from up to three turned sources.
TEST(CslVulkan, AgreesWithTheCpuOnAnInterpolatedFrame) {
  SKIP_WITHOUT_VULKAN();
  const Scene moving = scene_from_yaml(causticbench::testing::small_glass_sphere_turning());
  const PhaseKnobs knobs = csl_knobs({"rays_per_side=48", "image_size=128", "tracking_rays_per_side=16", "tracking_steps=2"});
  std::unique_ptr<CausticMethod> method = find_method("csl").create();
  const RestPose rest(moving, {0, 1});
  prepare_method(*method, rest.context(), knobs.build);
  ASSERT_EQ(method->record()["objects"][0]["light_sample_set"], "dynamic");
  const PosedFrame frame_one(moving, 1);
  method->update(frame_one.context(), knobs.frame);
  double interpolated = 0.0;
  for (const auto& [name, value] : method->counters()) interpolated = name == "interpolated_spot_lights" ? value : interpolated;
  ASSERT_GT(interpolated, 0.0) << "frame 1 should be interpolated";
  expect_backends_agree(*method, frame_one, kEvaluationKnobs, "interpolated frame");
  // A new frame replaces the uploaded spot lights: frame 0 (a precomputed direction's own set) agrees too.
  const PosedFrame frame_zero(moving, 0);
  method->update(frame_zero.context(), knobs.frame);
  expect_backends_agree(*method, frame_zero, {{}}, "frame 0 after frame 1");
}

// Shadow rays need the scene's ray tracer, which the kernel does not have: refused when the knobs are
// read, before any spot light is made.
TEST(CslVulkan, ShadowRaysOnTheDeviceAreAnInputError) {
  const std::string message = causticbench::testing::input_error_message(
      [] { csl_knobs({"backend=vulkan", "occlusion=shadow_rays"}); });
  EXPECT_NE(message.find("occlusion"), std::string::npos) << message;
  EXPECT_NE(message.find("backend is cpu"), std::string::npos) << message;
}

// backend came after csl's runs were recorded: at its default (cpu, what they did) it stays out of the
// run key, so they keep their keys (Keys.ShippedExperimentsKeepTheirRunKeys); vulkan enters it.
TEST(CslVulkan, OnlyTheVulkanBackendEntersTheRunKey) {
  const std::vector<ParamSpec>& specs = find_method("csl").info().params;
  auto key_params = [&](const std::string& backend) {
    ParamDict dict;
    dict.set_assignment("backend=" + backend, "test");
    return dict.resolve(specs, "csl").key_json(specs);
  };
  EXPECT_FALSE(key_params("cpu").contains("backend"));
  EXPECT_EQ(key_params("cpu"), ParamDict().resolve(specs, "csl").key_json(specs));
  EXPECT_EQ(key_params("vulkan").value("backend", ""), "vulkan");
  // occlusion applies on the CPU only, so a vulkan run's key has none.
  EXPECT_TRUE(key_params("cpu").contains("occlusion"));
  EXPECT_FALSE(key_params("vulkan").contains("occlusion"));
}

// The portable path: causticbench dumps a csl frame (here the CPU backend's), causticbench-gpubench
// replays it on the first Vulkan device, causticbench gpu-compare checks the two against the format's
// tolerances; a corrupted replay output is caught.
TEST(CslVulkan, DumpReplayCompareRoundTrip) {
  SKIP_WITHOUT_VULKAN();
  namespace fs = std::filesystem;
  const causticbench::testing::TemporaryFolder folder("csl_dump_test");
  std::ofstream(folder.path("scene.yaml")) << kSmallGlassSphere;
  const std::string dump = folder.path("dump");
  std::string output;
  int code = causticbench::testing::run_command(
      std::string(CAUSTICBENCH_BINARY) + " -q render " + folder.path("scene.yaml") +
          " --method csl --set rays_per_side=64 --set image_size=128 --out " + folder.path("out") + " --dump-frame " + dump,
      output);
  ASSERT_EQ(code, 0) << output;
  EXPECT_EQ(read_dump_method(dump), "csl");
  const CslFrameData frame = read_csl_frame_data(dump);
  EXPECT_EQ(frame.width, 40u);
  EXPECT_GT(frame.light_count(), 0u);
  EXPECT_GT(frame.image_count(), 0u);
  code = causticbench::testing::run_command(std::string(CAUSTICBENCH_GPUBENCH) + " " + dump + " --repetitions 2", output);
  ASSERT_EQ(code, 0) << output;
  EXPECT_NE(output.find("evaluations/s"), std::string::npos) << output;
  std::stringstream timings;
  timings << std::ifstream(dump + "/gpu_timings.json").rdbuf();
  EXPECT_NE(timings.str().find("\"method\": \"csl\""), std::string::npos) << timings.str();
  EXPECT_NE(timings.str().find("\"spot_lights\": " + std::to_string(frame.light_count())), std::string::npos) << timings.str();
  code = causticbench::testing::run_command(std::string(CAUSTICBENCH_BINARY) + " gpu-compare " + dump, output);
  EXPECT_EQ(code, 0) << output;
  EXPECT_NE(output.find("csl vulkan against cpu"), std::string::npos) << output;
  EXPECT_NE(output.find("): agree"), std::string::npos) << output;
  // A replay output that lost a tenth of a percent of its light disagrees.
  std::vector<float> wrong = read_floats(dump + "/vulkan_irradiance.bin");
  for (float& value : wrong) value *= 0.999f;
  write_floats(dump + "/vulkan_irradiance.bin", wrong);
  code = causticbench::testing::run_command(std::string(CAUSTICBENCH_BINARY) + " gpu-compare " + dump, output);
  EXPECT_EQ(code, 1) << output;
  // A damaged dump names the file: a spot light that reads an image the dump does not hold.
  std::vector<float> light_images = read_floats(dump + "/light_images.bin");
  light_images.resize(light_images.size() + 4, 0.0f);
  write_floats(dump + "/light_images.bin", light_images);
  code = causticbench::testing::run_command(std::string(CAUSTICBENCH_BINARY) + " gpu-compare " + dump, output);
  EXPECT_EQ(code, 2) << output;
  EXPECT_NE(output.find("lights and light_images disagree"), std::string::npos) << output;
}
