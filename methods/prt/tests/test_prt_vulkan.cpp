// prt's Vulkan backend (backend: vulkan: l = M L and the lookup in compute shaders,
// methods/prt/vulkan_prt.h) against its CPU backend: the glass sphere under a lobe at both precisions and
// two band counts, and two objects, one turned and scaled (records, build-space maps, the second object's
// offsets into the matrices and the incident field); and the dump -> causticbench-gpubench -> gpu-compare
// round trip. Skipped, saying why, where no Vulkan device exists.
#include <cmath>
#include <cstdio>
#include <fstream>

#include <gtest/gtest.h>

#include "core/image_statistics.h"
#include "methods/frame_dump.h"
#include "methods/prt/frame_data.h"
#include "tests/test_support.h"

using causticbench::testing::render;
using causticbench::testing::scene_from_yaml;
using namespace causticbench;

namespace {

#define SKIP_WITHOUT_VULKAN() CAUSTICBENCH_SKIP_WITHOUT_VULKAN("prt's backend: vulkan")

// The glass sphere of kSmallGlassSphere under a 0.5 sr lobe, and a mirror ring turned and scaled beside
// it: two objects, the second with a build space that is not the world's.
const char* const kTwoObjectsUnderALobe = R"(
camera: {position: [0, 2.2, 2.4], look_at: [0, 0.1, 0], fov_degrees: 45, resolution: [48, 40]}
lights: [{type: environment, procedural: gaussian_spot, direction: [0.3, -1, 0.2], irradiance: 1, solid_angle_sr: 0.5}]
objects:
  - shape: {type: quad, size: [6, 6]}
    material: {type: diffuse, albedo: 0.8}
  - shape: {type: sphere, radius: 0.4}
    material: {type: glass, ior: 1.5}
    transform: {translate: [-0.5, 0.6, 0]}
  - shape: {type: sphere, radius: 0.25}
    material: {type: mirror}
    transform: {translate: [0.6, 0.45, 0.2], rotate: [20, 35, 0], scale: 1.3}
)";

const std::vector<std::string> kSmallBuild = {"grid_resolution=12", "volume_radius=4", "source_directions=24",
                                              "photons_per_direction=3000"};

// Both backends on one scene and knob set: the images agree within prt's dump-format bounds
// (frame_replay.cpp; gpu-compare applies the same), and both count the same receiver points.
void expect_backends_agree(const std::string& scene_text, std::vector<std::string> knobs, const std::string& what) {
  knobs.insert(knobs.end(), kSmallBuild.begin(), kSmallBuild.end());
  const FrameDumpFormat& format = frame_dump_format("prt");
  const causticbench::testing::BackendRuns runs = causticbench::testing::expect_backends_agree(
      scene_from_yaml(scene_text), "prt", knobs, what, format.relmse_tolerance, format.flux_tolerance);
  EXPECT_EQ(causticbench::testing::counter_value(runs.vulkan, "receiver_points"),
            causticbench::testing::counter_value(runs.cpu, "receiver_points"))
      << runs.label;
}

std::string glass_sphere_under_a_lobe() {
  std::string text = causticbench::testing::kSmallGlassSphere;
  const std::string sun = "lights: [{type: directional, direction: [0.3, -1, 0.2], irradiance: 1}]";
  text.replace(text.find(sun), sun.size(),
               "lights: [{type: environment, procedural: gaussian_spot, direction: [0.3, -1, 0.2], irradiance: 1, "
               "solid_angle_sr: 0.5}]");
  return text;
}

}  // namespace

TEST(PrtVulkan, AgreesWithTheCpuOnTheGlassSphereAtBothPrecisions) {
  SKIP_WITHOUT_VULKAN();
  for (const char* bands : {"sh_order=3", "sh_order=5"})
    for (const char* precision : {"precision=float32", "precision=float16"})
      expect_backends_agree(glass_sphere_under_a_lobe(), {bands, precision}, "glass sphere");
}

TEST(PrtVulkan, AgreesWithTheCpuOnTwoObjectsOneTurnedAndScaled) {
  SKIP_WITHOUT_VULKAN();
  expect_backends_agree(kTwoObjectsUnderALobe, {"sh_order=4", "precision=float16"}, "two objects");
  expect_backends_agree(kTwoObjectsUnderALobe, {"sh_order=6", "window=hanning"}, "two objects");
}

// causticbench dumps a prt frame (the CPU backend's), causticbench-gpubench replays it on the first Vulkan
// device, causticbench gpu-compare checks the two; a replay output off by a percent disagrees, and a
// damaged dump names its file.
TEST(PrtVulkan, DumpReplayCompareRoundTrip) {
  SKIP_WITHOUT_VULKAN();
  const causticbench::testing::TemporaryFolder folder("prt_dump_test");
  std::ofstream(folder.path("scene.yaml")) << kTwoObjectsUnderALobe;
  const std::string dump = folder.path("dump");
  std::string knobs;
  for (const std::string& knob : kSmallBuild) knobs += " --set " + knob;
  std::string output;
  int code = causticbench::testing::run_command(std::string(CAUSTICBENCH_BINARY) + " -q render " + folder.path("scene.yaml") +
                                                    " --method prt --set sh_order=3 --set precision=float16" + knobs +
                                                    " --out " + folder.path("out") + " --dump-frame " + dump,
                                                output);
  ASSERT_EQ(code, 0) << output;
  EXPECT_EQ(read_dump_method(dump), "prt");
  const PrtFrameData frame = read_prt_frame_data(dump);
  EXPECT_EQ(frame.width, 48u);
  EXPECT_EQ(frame.object_count(), 2u);
  causticbench::testing::expect_replay_round_trip(CAUSTICBENCH_GPUBENCH, CAUSTICBENCH_BINARY, dump, "prt",
                                                  "\"cells\": " + std::to_string(2 * 12 * 12 * 12), "matrices.bin", 5,
                                                  "matrices.bin does not hold");
}
