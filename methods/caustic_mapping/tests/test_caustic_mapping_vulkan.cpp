// caustic_mapping's Vulkan backend (backend: vulkan: the light views rasterised, the leave and photon
// stages, sprites blended into the caustic map, the lookup; methods/caustic_mapping/vulkan_caustic_mapping.h)
// against its CPU backend on three scenes (a flat mirror, the glass sphere's two interfaces, a mirror
// sphere under a point light), with every splat kernel and both hit positions; the statistics both count;
// the refusal of exact rays on the device; and the dump -> causticbench-gpubench -> gpu-compare round
// trip. Skipped, saying why, where no Vulkan device exists.
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>

#include <gtest/gtest.h>

#include "core/image_statistics.h"
#include "gpu/vulkan_context.h"
#include "methods/caustic_mapping/frame_data.h"
#include "methods/frame_dump.h"
#include "tests/test_support.h"

using namespace causticbench;
using causticbench::testing::kFlatMirror;
using causticbench::testing::kMirrorSpherePointLight;
using causticbench::testing::kSmallGlassSphere;
using causticbench::testing::render;
using causticbench::testing::scene_from_yaml;

namespace {

#define SKIP_WITHOUT_VULKAN() CAUSTICBENCH_SKIP_WITHOUT_VULKAN("caustic_mapping's backend: vulkan")

// How far the backends may differ. Where the scene's surfaces are triangles to the ray tracer too (a
// quad mirror over a quad floor), the device repeats the CPU's every step on the same surfaces: only
// float against double and the rasteriser's order of adding splats part them, and the counts agree to
// the few photons whose float search reads a neighbouring texel. Where they are curved (spheres), the
// device rasterises them tessellated (2 x photon_resolution segments): chords inside the sphere and
// interpolated normals move photons, and the bounds are caustic_mapping's dump-format tolerances
// (methods/caustic_mapping/frame_replay.cpp, what gpu-compare applies), the counts within half a percent.
struct Bounds {
  double relmse, flux, counts, lost_flux;
};
const Bounds kSameSurfaces{1e-6, 1e-4, 1e-3, 1e-3};
Bounds tessellated() {
  const FrameDumpFormat& format = frame_dump_format("caustic_mapping");
  return {format.relmse_tolerance, format.flux_tolerance, 5e-3, 3e-3};
}

// Both backends on one scene and knob set: the images agree within `bounds`, and so do their counts.
void expect_backends_agree(const std::string& scene_text, const std::vector<std::string>& knobs, const std::string& what,
                           const Bounds& bounds) {
  const causticbench::testing::BackendRuns runs = causticbench::testing::expect_backends_agree(
      scene_from_yaml(scene_text), "caustic_mapping", knobs, what, bounds.relmse, bounds.flux);
  const FrameResult &cpu = runs.cpu, &vulkan = runs.vulkan;
  const std::string& text = runs.label;
  // The photons the device counts (covered texels, landed, receiver-map reads) are the CPU's within the
  // bounds' share.
  const auto counter = causticbench::testing::counter_value;
  std::printf("  photons %g / %g, landed %g / %g, reads %g / %g, lost %.4f / %.4f\n", counter(vulkan, "photons"),
              counter(cpu, "photons"), counter(vulkan, "photons_landed"), counter(cpu, "photons_landed"),
              counter(vulkan, "receiver_map_reads"), counter(cpu, "receiver_map_reads"),
              vulkan.lost_flux ? vulkan.lost_flux->fraction : -1.0, cpu.lost_flux ? cpu.lost_flux->fraction : -1.0);
  EXPECT_NEAR(counter(vulkan, "photons"), counter(cpu, "photons"), bounds.counts * counter(cpu, "photons")) << text;
  EXPECT_GT(counter(cpu, "photons_landed"), 0.0) << text;
  EXPECT_NEAR(counter(vulkan, "photons_landed"), counter(cpu, "photons_landed"), bounds.counts * counter(cpu, "photons"))
      << text;
  EXPECT_NEAR(counter(vulkan, "receiver_map_reads"), counter(cpu, "receiver_map_reads"),
              bounds.counts * counter(cpu, "receiver_map_reads")) << text;
  ASSERT_TRUE(cpu.lost_flux && vulkan.lost_flux);
  EXPECT_NEAR(vulkan.lost_flux->fraction, cpu.lost_flux->fraction, bounds.lost_flux) << text;
}

}  // namespace

TEST(CausticMappingVulkan, AgreesWithTheCpuOnAFlatMirrorForEverySplat) {
  SKIP_WITHOUT_VULKAN();
  for (const char* splat : {"splat=point", "splat=gaussian", "splat=variable"})
    expect_backends_agree(kFlatMirror, {splat, "photon_resolution=128", "caustic_map_resolution=128"}, "flat mirror",
                          kSameSurfaces);
  expect_backends_agree(kFlatMirror, {"hit_position=texel", "photon_resolution=128", "caustic_map_resolution=128"},
                        "flat mirror", kSameSurfaces);
}

TEST(CausticMappingVulkan, AgreesWithTheCpuOnTheGlassSphere) {
  SKIP_WITHOUT_VULKAN();
  expect_backends_agree(kSmallGlassSphere, {"photon_resolution=128", "caustic_map_resolution=128"}, "glass sphere",
                        tessellated());
  expect_backends_agree(kSmallGlassSphere,
                        {"photon_resolution=128", "caustic_map_resolution=96", "splat=gaussian", "splat_radius=3",
                         "search_iterations=2", "refraction=one_interface"},
                        "glass sphere", tessellated());
}

TEST(CausticMappingVulkan, AgreesWithTheCpuUnderAPointLight) {
  SKIP_WITHOUT_VULKAN();
  expect_backends_agree(kMirrorSpherePointLight, {"photon_resolution=128", "caustic_map_resolution=128"},
                        "mirror sphere, point light", tessellated());
  expect_backends_agree(kMirrorSpherePointLight,
                        {"photon_resolution=96", "caustic_map_resolution=128", "splat=variable", "splat_photons=4",
                         "max_splat_radius=4", "search_iterations=12"},
                        "mirror sphere, point light", tessellated());
}

// The device has no exact rays: intersection: exact with backend: vulkan is refused when the knobs are
// read, before any pass is rendered.
TEST(CausticMappingVulkan, ExactRaysOnTheDeviceAreAnInputError) {
  const std::string message = causticbench::testing::input_error_message(
      [] { causticbench::testing::method_knobs("caustic_mapping", {"intersection=exact", "backend=vulkan"}); });
  EXPECT_NE(message.find("backend"), std::string::npos) << message;
  EXPECT_NE(message.find("intersection is image_space"), std::string::npos) << message;
}

// causticbench dumps a caustic_mapping frame (the CPU backend's), causticbench-gpubench replays it (light
// views, leave and photon stages, splats, lookup) on the first Vulkan device, causticbench gpu-compare
// checks the two; a replay output off by a percent disagrees, and a damaged dump names its file.
TEST(CausticMappingVulkan, DumpReplayCompareRoundTrip) {
  SKIP_WITHOUT_VULKAN();
  const causticbench::testing::TemporaryFolder folder("caustic_mapping_dump_test");
  std::ofstream(folder.path("scene.yaml")) << kSmallGlassSphere;
  const std::string dump = folder.path("dump");
  std::string output;
  int code = causticbench::testing::run_command(
      std::string(CAUSTICBENCH_BINARY) + " -q render " + folder.path("scene.yaml") +
          " --method caustic_mapping --set photon_resolution=128 --set caustic_map_resolution=128 --out " +
          folder.path("out") + " --dump-frame " + dump,
      output);
  ASSERT_EQ(code, 0) << output;
  EXPECT_EQ(read_dump_method(dump), "caustic_mapping");
  const CausticMappingFrameData frame = read_caustic_mapping_frame_data(dump);
  EXPECT_EQ(frame.width, 40u);
  EXPECT_EQ(frame.pass_count(), 1u);
  EXPECT_GT(frame.photon_count(), 1000u);
  causticbench::testing::expect_replay_round_trip(CAUSTICBENCH_GPUBENCH, CAUSTICBENCH_BINARY, dump, "caustic_mapping",
                                                  "\"photon_buffer_texels\": " + std::to_string(frame.photon_count()),
                                                  "vertices.bin", 8, "vertices.bin is not whole triangles");
}
