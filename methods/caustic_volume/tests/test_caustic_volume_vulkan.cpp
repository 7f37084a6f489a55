// caustic_volume's Vulkan backend (backend: vulkan: the footprints rasterised over the image, each
// fragment's point tested in float; methods/caustic_volume/vulkan_caustic_volume.h) against its CPU
// backend on four scenes (a flat mirror, the ring seen from above with both intensities, the glass
// sphere through the object, a mirror sphere under a point light); the refusal of shadow rays on the
// device; and the dump -> causticbench-gpubench -> gpu-compare round trip. Skipped, saying why, where no
// Vulkan device exists.
#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>

#include <gtest/gtest.h>

#include "core/image_statistics.h"
#include "methods/caustic_volume/frame_data.h"
#include "methods/frame_dump.h"
#include "methods/caustic_volume/tests/scenes.h"
#include "tests/test_support.h"

using namespace causticbench;
using causticbench::testing::kFlatMirror;
using causticbench::testing::kMirrorSpherePointLight;
using causticbench::testing::kRingFromAbove;
using causticbench::testing::kSmallGlassSphere;
using causticbench::testing::render;
using causticbench::testing::scene_from_yaml;

namespace {

#define SKIP_WITHOUT_VULKAN() CAUSTICBENCH_SKIP_WITHOUT_VULKAN("caustic_volume's backend: vulkan")

const auto counter = causticbench::testing::counter_value;

// Both backends on one scene and knob set: the images agree within caustic_volume's dump-format bounds
// (frame_replay.cpp; gpu-compare applies the same), the points found lit within half a percent, and the
// device tests no more points than the CPU (its footprints are the hulls; the CPU's rows add a pixel).
void expect_backends_agree(const std::string& scene_text, const std::vector<std::string>& knobs, const std::string& what) {
  const FrameDumpFormat& format = frame_dump_format("caustic_volume");
  const causticbench::testing::BackendRuns runs = causticbench::testing::expect_backends_agree(
      scene_from_yaml(scene_text), "caustic_volume", knobs, what, format.relmse_tolerance, format.flux_tolerance);
  const FrameResult &cpu = runs.cpu, &vulkan = runs.vulkan;
  const std::string& text = runs.label;
  std::printf("  lit points %g / %g, tests %g / %g\n", counter(vulkan, "volume_hits"), counter(cpu, "volume_hits"),
              counter(vulkan, "volume_point_tests"), counter(cpu, "volume_point_tests"));
  EXPECT_GT(counter(cpu, "volume_hits"), 0.0) << text;
  EXPECT_NEAR(counter(vulkan, "volume_hits"), counter(cpu, "volume_hits"), 5e-3 * counter(cpu, "volume_hits")) << text;
  EXPECT_GT(counter(vulkan, "volume_point_tests"), counter(vulkan, "volume_hits")) << text;
  EXPECT_LE(counter(vulkan, "volume_point_tests"), counter(cpu, "volume_point_tests")) << text;
  EXPECT_EQ(counter(vulkan, "volumes"), counter(cpu, "volumes")) << text;
}

}  // namespace

TEST(CausticVolumeVulkan, AgreesWithTheCpuOnAFlatMirror) {
  SKIP_WITHOUT_VULKAN();
  for (const char* intensity : {"intensity=interpolated", "intensity=constant"})
    expect_backends_agree(kFlatMirror, {intensity}, "flat mirror");
}

TEST(CausticVolumeVulkan, AgreesWithTheCpuOnTheRing) {
  SKIP_WITHOUT_VULKAN();
  for (const char* intensity : {"intensity=interpolated", "intensity=constant"})
    expect_backends_agree(kRingFromAbove, {intensity, "tessellation=64"}, "ring");
}

TEST(CausticVolumeVulkan, AgreesWithTheCpuThroughAGlassSphereAndUnderAPointLight) {
  SKIP_WITHOUT_VULKAN();
  expect_backends_agree(kSmallGlassSphere, {"refraction=through_object", "tessellation=32"}, "glass sphere");
  expect_backends_agree(kMirrorSpherePointLight, {"tessellation=32"}, "mirror sphere, point light");
}

// The device traces no rays: occlusion: shadow_rays with backend: vulkan is refused when the knobs are
// read, before any volume is built.
TEST(CausticVolumeVulkan, ShadowRaysOnTheDeviceAreAnInputError) {
  const std::string message = causticbench::testing::input_error_message(
      [] { causticbench::testing::method_knobs("caustic_volume", {"occlusion=shadow_rays", "backend=vulkan"}); });
  EXPECT_NE(message.find("backend"), std::string::npos) << message;
  EXPECT_NE(message.find("occlusion is none"), std::string::npos) << message;
}

// causticbench dumps a caustic_volume frame (the CPU backend's), causticbench-gpubench replays it on the
// first Vulkan device, causticbench gpu-compare checks the two; a replay output off by a percent
// disagrees, and a damaged dump names its file.
TEST(CausticVolumeVulkan, DumpReplayCompareRoundTrip) {
  SKIP_WITHOUT_VULKAN();
  const causticbench::testing::TemporaryFolder folder("caustic_volume_dump_test");
  std::ofstream(folder.path("scene.yaml")) << kRingFromAbove;
  const std::string dump = folder.path("dump");
  std::string output;
  int code = causticbench::testing::run_command(std::string(CAUSTICBENCH_BINARY) + " -q render " + folder.path("scene.yaml") +
                                                    " --method caustic_volume --set tessellation=32 --out " +
                                                    folder.path("out") + " --dump-frame " + dump,
                                                output);
  ASSERT_EQ(code, 0) << output;
  EXPECT_EQ(read_dump_method(dump), "caustic_volume");
  const CausticVolumeFrameData frame = read_caustic_volume_frame_data(dump);
  EXPECT_EQ(frame.width, 128u);
  EXPECT_GT(frame.volume_count(), 100u);
  causticbench::testing::expect_replay_round_trip(CAUSTICBENCH_GPUBENCH, CAUSTICBENCH_BINARY, dump, "caustic_volume",
                                                  "\"volumes\": " + std::to_string(frame.volume_count()), "volumes.bin",
                                                  5, "volumes.bin is not whole volumes");
}
