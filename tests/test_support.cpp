#include "tests/test_support.h"

#include "methods/frame_dump.h"

#include <algorithm>
#include <array>
#include <cstdio>
#include <fstream>
#include <memory>
#include <sstream>
#include <regex>
#include <stdexcept>

#include <sys/wait.h>

#include <gtest/gtest.h>

#include "core/assets.h"
#include "core/image_statistics.h"
#include "gpu/vulkan_context.h"

namespace causticbench::testing {

const char* const kMirrorSpherePointLight = R"(
camera: {position: [0, 2.5, 3.0], look_at: [0, 0, 0], fov_degrees: 50, resolution: [48, 48]}
lights: [{type: point, position: [0.3, 2.0, 0.2], intensity: 5}]
objects:
  - shape: {type: quad, size: [8, 8]}
    material: {type: diffuse, albedo: 0.8}
  - shape: {type: sphere, radius: 0.4}
    material: {type: mirror, reflectance: 0.9}
    transform: {translate: [0, 0.6, 0]}
)";

BackendRuns expect_backends_agree(const Scene& scene, const std::string& method, const std::vector<std::string>& knobs,
                                  const std::string& what, double relmse_bound, double flux_bound) {
  std::vector<std::string> vulkan_knobs = knobs;
  vulkan_knobs.push_back("backend=vulkan");
  BackendRuns runs{render(scene, method, knobs), render(scene, method, vulkan_knobs), what};
  for (const std::string& knob : knobs) runs.label += " " + knob;
  const std::vector<uint8_t>& receivers = runs.cpu.gbuffer.receiver;
  const double cpu_flux = masked_sum(runs.cpu.caustic, receivers);
  EXPECT_GT(cpu_flux, 0.0) << runs.label;
  if (!(cpu_flux > 0.0)) return runs;
  const double relmse = relative_mse(runs.vulkan.caustic, runs.cpu.caustic, receivers);
  const double flux = masked_sum(runs.vulkan.caustic, receivers) / cpu_flux - 1.0;
  std::printf("%s: vulkan against cpu relMSE %.3g, flux %+.3g\n", runs.label.c_str(), relmse, flux);
  EXPECT_LT(relmse, relmse_bound) << runs.label;
  EXPECT_LT(std::abs(flux), flux_bound) << runs.label;
  return runs;
}

void expect_replay_round_trip(const std::string& gpubench, const std::string& binary, const std::string& dump,
                              const std::string& method, const std::string& fact, const std::string& damaged_file,
                              size_t cut, const std::string& damage_message) {
  std::string output;
  int code = run_command(gpubench + " " + dump + " --repetitions 2", output);
  ASSERT_EQ(code, 0) << output;
  std::stringstream timings;
  timings << std::ifstream(dump + "/gpu_timings.json").rdbuf();
  EXPECT_NE(timings.str().find("\"method\": \"" + method + "\""), std::string::npos) << timings.str();
  EXPECT_NE(timings.str().find(fact), std::string::npos) << timings.str();
  code = run_command(binary + " gpu-compare " + dump, output);
  EXPECT_EQ(code, 0) << output;
  EXPECT_NE(output.find("): agree"), std::string::npos) << output;
  std::vector<float> wrong = read_floats(dump + "/vulkan_irradiance.bin");
  for (float& value : wrong) value *= 0.99f;
  write_floats(dump + "/vulkan_irradiance.bin", wrong);
  code = run_command(binary + " gpu-compare " + dump, output);
  EXPECT_EQ(code, 1) << output;
  std::vector<float> damaged = read_floats(dump + "/" + damaged_file);
  ASSERT_GT(damaged.size(), cut);
  damaged.resize(damaged.size() - cut);
  write_floats(dump + "/" + damaged_file, damaged);
  code = run_command(binary + " gpu-compare " + dump, output);
  EXPECT_EQ(code, 2) << output;
  EXPECT_NE(output.find(damage_message), std::string::npos) << output;
}

glm::dvec3 random_direction(Random& random) {
  const double z = 1.0 - 2.0 * random.uniform_double(), phi = 2.0 * kPiDouble * random.uniform_double();
  const double s = std::sqrt(std::max(0.0, 1.0 - z * z));
  return {s * std::cos(phi), s * std::sin(phi), z};
}

double counter_value(const FrameResult& result, const std::string& name) {
  for (const auto& [key, value] : result.counters)
    if (key == name) return value;
  return -1.0;
}

const char* const kFlatMirror = R"(
camera: {type: orthographic, position: [1.5, 1.0, 0], look_at: [1.5, 0, 0], up: [0, 0, 1], view_height: 1.2, resolution: [96, 96]}
lights: [{type: directional, direction: [1, -1, 0], irradiance: 2}]
objects:
  - shape: {type: quad, size: [8, 8]}
    material: {type: diffuse, albedo: 0.8}
  - shape: {type: quad, size: [0.6, 0.6]}
    material: {type: mirror, reflectance: 0.9}
    transform: {translate: [1.5, 1.5, 0], rotate: [0, 0, 112.5]}
)";

const char* const kSmallGlassSphere = R"(
camera: {position: [0, 2.0, 2.0], look_at: [0, 0.1, 0], fov_degrees: 35, resolution: [40, 40]}
lights: [{type: directional, direction: [0.3, -1, 0.2], irradiance: 1}]
objects:
  - shape: {type: quad, size: [6, 6]}
    material: {type: diffuse, albedo: 0.8}
  - shape: {type: sphere, radius: 0.4}
    material: {type: glass, ior: 1.5}
    transform: {translate: [0, 0.6, 0]}
)";

const std::vector<std::string> kSmallSceneReferenceKnobs = {"photons_per_pass=200000", "max_passes=6", "min_passes=1",
                                                             "target_error=0", "max_seconds=0", "seed=7"};

Scene scene_from_yaml(const std::string& yaml, const std::string& name) {
  return load_scene_from_string(yaml, name, ".");
}

FrameResult render(const Scene& scene, const std::string& method, const std::vector<std::string>& knobs, int frame) {
  RenderRequest request;
  request.scene = &scene;
  request.method = method;
  request.frame = frame;
  for (const std::string& knob : knobs) request.params.set_assignment(knob, "test");
  CheckedRequest checked = check_request(request);
  return run_frame(request, checked);
}

FrameResult render_sequence(const Scene& scene, const std::string& method, const std::vector<std::string>& knobs,
                            const std::vector<int>& frames, int judged) {
  RenderRequest request;
  request.scene = &scene;
  request.method = method;
  request.frame = judged;
  for (const std::string& knob : knobs) request.params.set_assignment(knob, "test");
  const auto position = std::find(frames.begin(), frames.end(), judged);
  if (position == frames.end()) throw std::logic_error("render_sequence: the judged frame is not played");
  for (int frame : frames) {
    request.frame = frame;
    check_request(request);  // each frame inside the animation
  }
  request.frame = judged;
  CheckedRequest checked = check_request(request);
  const MethodInfo& info = checked.method->info();
  std::unique_ptr<CausticMethod> instance = checked.method->create();
  const PhaseKnobs phases = split_phases(checked.params, info.params);
  std::vector<std::unique_ptr<PosedFrame>> posed;
  std::vector<const PosedFrame*> sequence;
  const PosedFrame* frame_zero = nullptr;
  for (int frame : frames) {
    posed.push_back(std::make_unique<PosedFrame>(scene, frame));
    sequence.push_back(posed.back().get());
    if (frame == 0) frame_zero = posed.back().get();
  }
  std::unique_ptr<RestPose> rest;
  FrameResult result;
  result.prepare = prepare_method(*instance, prepare_context(scene, frames, frame_zero, rest), phases.build);
  result.timings.prepare_seconds = result.prepare.prepare_seconds;
  std::vector<SequenceOutput> outputs =
      play_sequence(*instance, sequence, phases.frame, {phases.render}, TimingProtocol{false, 1});
  const size_t index = static_cast<size_t>(position - frames.begin());
  const FrameTimings& timings = outputs.front().timings.at(index);
  result.timings.update_milliseconds = timings.update_ms.front();
  result.timings.render_milliseconds = timings.render_ms.front();
  result.caustic = std::move(outputs.front().images.at(index));
  result.gbuffer = std::move(posed.at(index)->gbuffer);
  result.memory_bytes = instance->memory_bytes();
  result.counters = instance->counters();
  result.method_record = instance->record();
  return result;
}

TemporaryFolder::TemporaryFolder(const std::string& name)
    : path_(std::filesystem::temp_directory_path() / ("causticbench_" + name)) {
  std::filesystem::remove_all(path_);
  std::filesystem::create_directories(path_);
}

TemporaryFolder::~TemporaryFolder() {
  std::error_code ignored;
  std::filesystem::remove_all(path_, ignored);
}

std::string TemporaryFolder::write(const std::string& name, const std::string& text) const {
  std::ofstream(path_ / name) << text;
  return (path_ / name).string();
}

std::string TemporaryFolder::path(const std::string& name) const { return (path_ / name).string(); }

std::string replace_once(std::string text, const std::string& from, const std::string& to) {
  size_t at = text.find(from);
  EXPECT_NE(at, std::string::npos) << "'" << from << "' not found";
  if (at == std::string::npos) return text;
  return text.replace(at, from.size(), to);
}

std::string small_glass_sphere_turning(const std::string& scene) {
  return "frames: 2\n" + replace_once(scene, "direction: [0.3, -1, 0.2], irradiance: 1",
                                       "direction: [0.3, -1, 0.2], irradiance: 1, animation: {keyframes: [{frame: 0, "
                                       "direction: [0.3, -1, 0.2]}, {frame: 1, direction: [-0.1, -1, 0.1]}]}");
}

PhaseKnobs method_knobs(const std::string& method, const std::vector<std::string>& knobs) {
  const MethodEntry& entry = find_method(method);
  ParamDict dict;
  for (const std::string& knob : knobs) dict.set_assignment(knob, "test");
  return split_phases(dict.resolve(entry.info().params, method), entry.info().params);
}

std::string tiny_experiment(const std::string& text, int resolution) {
  const std::string size = std::to_string(resolution);
  return replace_lines(
      text, {{"\noverrides:[^\n]*(\n  [^\n]*)*", "\noverrides: {resolution: [" + size + ", " + size + "]}"},
             {"\nreference:[^\n]*(\n  [^\n]*)*", "\nreference: {photons_per_pass: 100000, max_passes: 2, target_error: 0}"},
             {"\nrepetitions: [^\n]*", "\nrepetitions: 1"}});
}

std::string replace_lines(std::string text, const std::vector<std::pair<std::string, std::string>>& lines) {
  for (const auto& [pattern, replacement] : lines) {
    const std::regex expression(pattern);
    EXPECT_TRUE(std::regex_search(text, expression)) << "no line matches " << pattern;
    text = std::regex_replace(text, expression, replacement);
  }
  return text;
}

std::string shipped_scenes() {
  // The tree this build came from; once it is gone (an installed causticbench-conformance), the copy
  // cmake/sdk.cmake installs beside the executable.
  if (std::filesystem::is_directory(CAUSTICBENCH_SCENES)) return CAUSTICBENCH_SCENES;
  return installed_data_folder() + "/configs/scenes";
}

std::vector<std::filesystem::path> shipped_experiments(const std::string& prefix) {
  std::vector<std::filesystem::path> files;
  for (const auto& entry : std::filesystem::directory_iterator(std::string(CAUSTICBENCH_SCENES) + "/../experiments"))
    if (entry.path().extension() == ".yaml" && entry.path().filename().string().rfind(prefix, 0) == 0)
      files.push_back(entry.path());
  std::sort(files.begin(), files.end());
  return files;
}

std::string no_vulkan_device() {
  try {
    gpu::Context context;
    return "";
  } catch (const std::exception& error) {
    return error.what();
  }
}

std::string input_error_message(const std::function<void()>& action) {
  try {
    action();
  } catch (const InputError& error) {
    return error.what();
  }
  return "no error";
}

std::string read_whole_file(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

int run_command(const std::string& command, std::string& output) {
  output.clear();
  FILE* pipe = popen((command + " 2>&1").c_str(), "r");
  if (!pipe) return -1;
  std::array<char, 4096> buffer{};
  size_t read;
  while ((read = fread(buffer.data(), 1, buffer.size(), pipe)) > 0) output.append(buffer.data(), read);
  int status = pclose(pipe);
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

}  // namespace causticbench::testing
