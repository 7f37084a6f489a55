#include "tests/test_support.h"

#include <array>
#include <cstdio>
#include <fstream>

#include <sys/wait.h>

#include <gtest/gtest.h>

namespace causticbench::testing {

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
                                                             "target_noise_floor=0", "max_seconds=0", "seed=7"};

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
