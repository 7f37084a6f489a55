// lpi's Vulkan backend (methods/lpi/lpi.comp) against its CPU backend, on whichever device the
// runtime picks (lavapipe here): the kernel repeats the CPU lookup, so the two agree to float
// rounding. And the portable path: --dump-frame, causticbench-gpubench, gpu-compare.
#include <filesystem>
#include <fstream>
#include <sstream>

#include <gtest/gtest.h>

#include "core/image_statistics.h"
#include "gpu/vulkan_context.h"
#include "methods/frame_dump.h"
#include "methods/lifecycle.h"
#include "methods/registry.h"
#include "tests/test_support.h"

using namespace causticbench;
using causticbench::testing::render_sequence;
using causticbench::testing::scene_from_yaml;

namespace {

// A glass sphere and a mirror ring over a floor (two volumes that add where they overlap), under a
// sun that turns between frames 0 and 2: at frame 1 its direction in each object's frame lies between
// light samples, and the ring turns as well.
const char* const kTwoObjects = R"(
frames: 3
camera: {type: orthographic, position: [0.2, 3, 0], look_at: [0.2, 0, 0], up: [0, 0, 1], view_height: 3.2, resolution: [40, 40]}
lights:
  - type: directional
    direction: [0.3, -1, 0.2]
    irradiance: 1
    animation: {keyframes: [{frame: 0, direction: [0.3, -1, 0.2]}, {frame: 2, direction: [-0.35, -1, 0.05]}]}
objects:
  - shape: {type: quad, size: [8, 8]}
    material: {type: diffuse, albedo: 0.8}
  - shape: {type: sphere, radius: 0.35}
    material: {type: glass, ior: 1.5}
    transform: {translate: [-0.4, 0.5, 0.1]}
  - shape: {type: ring, radius: 0.45, height: 0.3}
    material: {type: mirror, reflectance: 0.9}
    animation: {keyframes: [{frame: 0, translate: [0.6, 0.15, 0], rotate: [0, 0, 0]}, {frame: 2, translate: [0.6, 0.15, 0], rotate: [0, 50, 0]}]}
)";

struct Agreement {
  double relmse, flux_ratio, cpu_flux;
};

Agreement cpu_against_vulkan(const Scene& scene, std::vector<std::string> knobs) {
  const FrameResult cpu = render_sequence(scene, "lpi", knobs, {0, 1}, 1);
  knobs.push_back("backend=vulkan");
  const FrameResult vulkan = render_sequence(scene, "lpi", knobs, {0, 1}, 1);
  EXPECT_FALSE(vulkan.method_record["gpu_device"].get<std::string>().empty());
  const double cpu_flux = masked_sum(cpu.caustic, cpu.gbuffer.receiver);
  return {relative_mse(vulkan.caustic, cpu.caustic, cpu.gbuffer.receiver),
          masked_sum(vulkan.caustic, cpu.gbuffer.receiver) / cpu_flux, cpu_flux};
}

}  // namespace

// The moving sun at frame 1 reads three light samples of the geodesic set per object (barycentric),
// through grid and shells, in every precision, orientation, outside mode and blend: relMSE < 1e-6 and
// flux within 1e-4, the bounds of pinhole's backends, since here too only the order and rounding of
// the float arithmetic differ (and the shells' cell is located with float side tests, not double).
TEST(LpiVulkan, AgreesWithTheCpuBackendOnGridAndShells) {
  CAUSTICBENCH_SKIP_WITHOUT_VULKAN("lpi's backend: vulkan");
  const Scene scene = scene_from_yaml(kTwoObjects);
  const std::vector<std::string> base = {"photons_per_sample=4000", "light_subdivision=0", "volume_radius=2.5"};
  const std::vector<std::vector<std::string>> cases = {
      {"storage=grid", "grid_resolution=20", "blend=barycentric", "orientation=paper"},
      {"storage=shells", "shell_count=8", "shell_subdivision=3", "blend=barycentric", "outside=fade", "orientation=paper"},
      {"storage=grid", "grid_resolution=17", "blend=aligned", "orientation=vector", "precision=uint8", "outside=zero"},
      {"storage=shells", "shell_count=6", "shell_subdivision=2", "shell_spacing=quadratic", "blend=nearest",
       "orientation=vector", "precision=float16"},
      {"storage=shells", "shell_count=8", "shell_subdivision=3", "blend=aligned", "precision=uint8", "orientation=paper"},
      {"storage=grid", "grid_resolution=16", "symmetry=axial", "precision=float16", "orientation=paper"},
  };
  for (std::vector<std::string> knobs : cases) {
    knobs.insert(knobs.end(), base.begin(), base.end());
    std::string label;
    for (const std::string& knob : knobs) label += knob + " ";
    const Agreement agreement = cpu_against_vulkan(scene, knobs);
    ASSERT_GT(agreement.cpu_flux, 0.0) << label;
    EXPECT_LT(agreement.relmse, 1e-6) << label;
    EXPECT_NEAR(agreement.flux_ratio, 1.0, 1e-4) << label;
  }
}

// At its default the backend stays out of the run key and of the build key (runs and stored builds
// from before the knob keep theirs); vulkan is another run with a build of its own.
TEST(LpiVulkan, CpuKeepsOldRunAndBuildKeys) {
  const MethodInfo& info = find_method("lpi").info();
  auto resolve = [&](const std::vector<std::string>& knobs) {
    ParamDict dict;
    for (const std::string& knob : knobs) dict.set_assignment(knob, "test_lpi_vulkan");
    return dict.resolve(info.params, "lpi");
  };
  const ParamSet unset = resolve({"storage=shells"}), cpu = resolve({"storage=shells", "backend=cpu"}),
                 vulkan = resolve({"storage=shells", "backend=vulkan"});
  EXPECT_EQ(unset.key_json(info.params), cpu.key_json(info.params));
  EXPECT_FALSE(cpu.key_json(info.params).contains("backend"));
  EXPECT_NE(cpu.key_json(info.params), vulkan.key_json(info.params));
  const Scene scene = scene_from_yaml(kTwoObjects);
  RestPose rest(scene, {0, 1});
  std::unique_ptr<CausticMethod> probe = create_method("lpi");
  const nlohmann::json cpu_build = *probe->build_cache()->build_dependencies(rest.context(), split_phases(cpu, info.params).build);
  EXPECT_FALSE(cpu_build["build"].contains("backend"));
  EXPECT_NE(cpu_build, *probe->build_cache()->build_dependencies(rest.context(), split_phases(vulkan, info.params).build));
}

// What the kernel does not evaluate is refused before any photon is shot, saying what it does.
TEST(LpiVulkan, RefusesStorageItDoesNotEvaluate) {
  const Scene scene = scene_from_yaml(causticbench::testing::kSmallGlassSphere);
  for (const char* storage : {"storage=multires", "storage=sh"}) {
    const std::string message = causticbench::testing::input_error_message([&] {
      causticbench::testing::render(scene, "lpi", {storage, "backend=vulkan", "photons_per_sample=1000"});
    });
    EXPECT_NE(message.find("backend vulkan needs the Vulkan kernel, which evaluates storage grid and shells"),
              std::string::npos)
        << message;
  }
  // --dump-frame writes the kernel's inputs, so it is refused the same way, before the photons are shot.
  causticbench::testing::TemporaryFolder folder("causticbench_lpi_dump_refused");
  const std::string path = folder.write("scene.yaml", causticbench::testing::kSmallGlassSphere);
  std::string output;
  const int code = causticbench::testing::run_command(std::string(CAUSTICBENCH_BINARY) + " render " + path +
                                                          " --method lpi --set storage=multires --out " + folder.path("out") +
                                                          " --dump-frame " + folder.path("dump"),
                                                      output);
  EXPECT_EQ(code, 2) << output;
  EXPECT_NE(output.find("--dump-frame (the Vulkan kernel's inputs) needs the Vulkan kernel"), std::string::npos) << output;
  EXPECT_EQ(output.find("lpi light samples"), std::string::npos) << "shot photons before refusing: " << output;
}

// The portable path for GPU machines: causticbench dumps an lpi frame (CPU backend), causticbench-gpubench
// replays it on the first Vulkan device, causticbench gpu-compare finds the two in agreement.
TEST(LpiVulkan, GpubenchReplaysADumpedFrame) {
  CAUSTICBENCH_SKIP_WITHOUT_VULKAN("lpi's backend: vulkan");
  causticbench::testing::TemporaryFolder folder("causticbench_lpi_dump_test");
  const std::string scene = folder.write("scene.yaml", kTwoObjects);
  const std::string dump = folder.path("dump");
  std::string output;
  for (const char* storage : {"storage=shells --set shell_count=8 --set shell_subdivision=3", "storage=grid"}) {
    int code = causticbench::testing::run_command(
        std::string(CAUSTICBENCH_BINARY) + " -q render " + scene + " --method lpi --frame 1 --set " + storage +
            " --set photons_per_sample=4000 --set light_samples=all --set light_subdivision=0 --out " +
            folder.path("out") + " --dump-frame " + dump,
        output);
    ASSERT_EQ(code, 0) << output;
    EXPECT_EQ(read_dump_method(dump), "lpi");
    code = causticbench::testing::run_command(std::string(CAUSTICBENCH_GPUBENCH) + " " + dump + " --repetitions 2", output);
    ASSERT_EQ(code, 0) << output;
    EXPECT_NE(output.find("receiver points"), std::string::npos) << output;
    std::stringstream timings;
    timings << std::ifstream(dump + "/gpu_timings.json").rdbuf();
    EXPECT_NE(timings.str().find("\"method\": \"lpi\""), std::string::npos) << timings.str();
    EXPECT_NE(timings.str().find("\"storage\": "), std::string::npos) << timings.str();
    // The sun at frame 1 lies between light samples: each of the two objects blends three.
    EXPECT_NE(timings.str().find("\"light_reads\": 6"), std::string::npos) << timings.str();
    code = causticbench::testing::run_command(std::string(CAUSTICBENCH_BINARY) + " gpu-compare " + dump, output);
    EXPECT_EQ(code, 0) << output;
    EXPECT_NE(output.find("lpi vulkan against cpu"), std::string::npos) << output;
    EXPECT_NE(output.find("): agree"), std::string::npos) << output;
  }
  // A replay whose values differ from the CPU's is caught: one stored value of the grid changed.
  std::vector<float> values = read_floats(dump + "/values.bin");
  std::vector<float> cpu = read_floats(dump + "/cpu_irradiance.bin");
  ASSERT_FALSE(values.empty());
  for (float& value : values) value *= 1.01f;  // float32: the words are the values
  write_floats(dump + "/values.bin", values);
  int code = causticbench::testing::run_command(std::string(CAUSTICBENCH_GPUBENCH) + " " + dump + " --repetitions 1", output);
  ASSERT_EQ(code, 0) << output;
  code = causticbench::testing::run_command(std::string(CAUSTICBENCH_BINARY) + " gpu-compare " + dump, output);
  EXPECT_EQ(code, 1) << output;
}
