// Input that used to abort in the tracer or be accepted without a word: degenerate cameras (at any frame,
// after any override), duplicate YAML keys, experiment names that leave their results folder, filters
// that select nothing, negative thread counts, repeated frames, empty metric lists, and EXR files that
// differ only in their date. Each is an input error naming file, line, key, expected and found; on the
// command line, exit code 2 with nothing written.
#include <chrono>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <thread>

#include <gtest/gtest.h>

#include "core/camera.h"
#include "core/files.h"
#include "core/image.h"
#include "core/scene.h"
#include "experiments/experiment.h"
#include "tests/test_support.h"

using namespace causticbench;
using causticbench::testing::input_error_message;
using causticbench::testing::run_command;
namespace fs = std::filesystem;

namespace {

const fs::path kCorpus = fs::path(__FILE__).parent_path() / "reliability";

// A fresh empty folder under the system's temporary folder, removed at the end of the test.
class TemporaryFolder {
 public:
  explicit TemporaryFolder(const std::string& name)
      : path_(fs::temp_directory_path() / ("causticbench_reliability_" + name)) {
    fs::remove_all(path_);
    fs::create_directories(path_);
  }
  ~TemporaryFolder() { fs::remove_all(path_); }
  fs::path path(const std::string& name) const { return path_ / name; }
  std::string write(const std::string& name, const std::string& text) const {
    std::ofstream(path_ / name) << text;
    return (path_ / name).string();
  }

 private:
  fs::path path_;
};

// The corpus files: every `bad_*.yaml`, sorted so that the test names are stable.
std::vector<std::string> corpus_files() {
  std::vector<std::string> names;
  for (const auto& entry : fs::directory_iterator(kCorpus)) {
    std::string name = entry.path().filename().string();
    if (name.rfind("bad_", 0) == 0 && entry.path().extension() == ".yaml") names.push_back(name);
  }
  std::sort(names.begin(), names.end());
  return names;
}

// The `# expect: ` fragments of a corpus file's comments.
std::vector<std::string> expected_fragments(const std::string& text) {
  const std::string marker = "# expect: ";
  std::vector<std::string> fragments;
  std::stringstream lines(text);
  for (std::string line; std::getline(lines, line);) {
    if (line.rfind(marker, 0) == 0) fragments.push_back(line.substr(marker.size()));
  }
  return fragments;
}

bool is_experiment(const std::string& text) {
  return text.rfind("methods:", 0) == 0 || text.find("\nmethods:") != std::string::npos;
}

// The message of loading `path` as the command line would, with the corpus folder dropped from the
// paths, so that the fragments can name files as the corpus writes them.
std::string load_error(const fs::path& path) {
  std::string text = read_text(path.string());
  std::string message = input_error_message([&] {
    if (is_experiment(text)) {
      load_experiment(path.string());
    } else {
      load_scene(path.string());
    }
  });
  const std::string prefix = kCorpus.string() + "/";
  for (size_t at; (at = message.find(prefix)) != std::string::npos;) message.erase(at, prefix.size());
  return message;
}

std::string shell_quoted(const fs::path& path) { return "'" + path.string() + "'"; }

// Runs the causticbench binary with `arguments`; its stdout and stderr go to `output`.
int causticbench_command(const std::string& arguments, std::string& output) {
  return run_command(std::string(CAUSTICBENCH_BINARY) + " --quiet " + arguments, output);
}

bool is_missing_or_empty(const fs::path& folder) { return !fs::exists(folder) || fs::is_empty(folder); }

// A valid experiment on the corpus scene, written into `folder`, for the command-line checks.
std::string write_valid_experiment(const TemporaryFolder& folder) {
  return folder.write("valid.yaml", "name: valid\nscene: " + (kCorpus / "scene.yaml").string() +
                                        "\nrepetitions: 1\n"
                                        "reference: {photons_per_pass: 10000, max_passes: 1, target_noise_floor: 0}\n"
                                        "methods:\n  - method: photon_map\n    sweep: {photons: [1000, 2000]}\n");
}

}  // namespace

// Each corpus file is refused with every fragment of its `# expect:` lines in the message.
class Corpus : public ::testing::TestWithParam<std::string> {};

TEST_P(Corpus, IsRefusedWithItsMessage) {
  fs::path path = kCorpus / GetParam();
  std::vector<std::string> fragments = expected_fragments(read_text(path.string()));
  ASSERT_FALSE(fragments.empty()) << GetParam() << " has no '# expect: ' line";
  std::string message = load_error(path);
  for (const std::string& fragment : fragments) EXPECT_NE(message.find(fragment), std::string::npos) << message;
}

INSTANTIATE_TEST_SUITE_P(Reliability, Corpus, ::testing::ValuesIn(corpus_files()),
                         [](const ::testing::TestParamInfo<std::string>& info) {
                           return fs::path(info.param).stem().string();
                         });

TEST(ReliabilityCamera, ValidAnimatedCameraAndItsScenesStillLoad) {
  EXPECT_EQ(load_error(kCorpus / "scene.yaml"), "no error");
  EXPECT_EQ(load_error(kCorpus / "animated_scene.yaml"), "no error");
}

TEST(ReliabilityCamera, CameraFrameRefusesADegenerateCameraInsteadOfTracingNaN) {
  Camera camera;
  camera.up = glm::dvec3(0.0);
  EXPECT_THROW(CameraFrame(camera, 0.0), std::logic_error);
  camera.up = glm::dvec3(0, 1, 0);
  camera.look_at = camera.position;
  EXPECT_THROW(CameraFrame(camera, 0.0), std::logic_error);
}

// The crash as the issue reported it: `render` aborted in Embree (exit 134) and left an empty folder.
TEST(ReliabilityCamera, RenderOfADegenerateCameraExitsTwoAndWritesNothing) {
  TemporaryFolder folder("render_camera");
  for (const char* scene : {"bad_camera_up_tiny.yaml", "bad_camera_keyframe_reaches_look_at.yaml"}) {
    std::string output;
    fs::path out = folder.path(std::string("out_") + scene);
    int code = causticbench_command(
        "render " + shell_quoted(kCorpus / scene) + " --method photon_map --out " + shell_quoted(out), output);
    EXPECT_EQ(code, 2) << output;
    EXPECT_NE(output.find(std::string(scene) + ":"), std::string::npos) << output;
    EXPECT_NE(output.find("key 'camera."), std::string::npos) << output;
    EXPECT_FALSE(fs::exists(out)) << output;
  }
}

TEST(ReliabilityCamera, RunWithADegenerateOverrideExitsTwoAndWritesNothing) {
  TemporaryFolder folder("run_camera");
  for (const char* experiment : {"bad_override_position_on_look_at.yaml", "bad_variant_position_on_look_at.yaml"}) {
    std::string output;
    fs::path results = folder.path(std::string("results_") + experiment);
    std::string arguments = "run " + shell_quoted(kCorpus / experiment) + " --results " + shell_quoted(results);
    int code = causticbench_command(arguments, output);
    EXPECT_EQ(code, 2) << output;
    EXPECT_NE(output.find(std::string(experiment) + ":"), std::string::npos) << output;
    EXPECT_NE(output.find(".camera."), std::string::npos) << output;
    EXPECT_FALSE(fs::exists(results)) << output;
  }
}

TEST(ReliabilityDuplicateKeys, ValidateExitsTwoNamingBothLocations) {
  std::string output;
  int code = causticbench_command("validate " + shell_quoted(kCorpus / "bad_duplicate_sweep.yaml"), output);
  EXPECT_EQ(code, 2) << output;
  EXPECT_NE(output.find("bad_duplicate_sweep.yaml:9:5: duplicate key 'sweep'"), std::string::npos) << output;
  EXPECT_NE(output.find("first at "), std::string::npos) << output;
  EXPECT_NE(output.find("bad_duplicate_sweep.yaml:7:5"), std::string::npos) << output;
}

TEST(ReliabilityDuplicateKeys, InScenesGivenAsText) {
  std::string scene = R"(camera: {position: [0, 2, 3], look_at: [0, 0, 0], resolution: [16, 16]}
lights: [{type: directional, direction: [0, -1, 0], irradiance: 1, irradiance: 2}]
objects: [{shape: {type: quad, size: [4, 4]}, material: {type: diffuse, albedo: 0.5}}]
)";
  std::string message = input_error_message([&] { load_scene_from_string(scene, "text.yaml", "."); });
  EXPECT_NE(message.find("text.yaml:2:68: duplicate key 'irradiance' in 'lights[0]'"), std::string::npos) << message;
  EXPECT_NE(message.find("first at text.yaml:2:53"), std::string::npos) << message;
}

// `..` wrote runs and report into the parent of --results; the parent must stay untouched.
TEST(ReliabilityNames, RunOfAnEscapingNameExitsTwoAndWritesNothing) {
  TemporaryFolder folder("run_name");
  fs::path parent = folder.path("parent");
  std::string output;
  int code = causticbench_command("run " + shell_quoted(kCorpus / "bad_name_dotdot.yaml") + " --results " +
                                      shell_quoted(parent / "results"), output);
  EXPECT_EQ(code, 2) << output;
  EXPECT_NE(output.find("bad_name_dotdot.yaml:4:1: key 'name'"), std::string::npos) << output;
  EXPECT_TRUE(is_missing_or_empty(parent)) << output;
}

TEST(ReliabilityNames, AFileNamedAfterAStoreFolderNeedsAName) {
  TemporaryFolder folder("file_name");
  std::string path = folder.write("references.yaml", "scene: " + (kCorpus / "scene.yaml").string() +
                                                         "\nmethods:\n  - method: photon_map\n");
  std::string message = input_error_message([&] { load_experiment(path); });
  EXPECT_NE(message.find("key 'name'"), std::string::npos) << message;
  EXPECT_NE(message.find("'references' (from the file name; set `name:`)"), std::string::npos) << message;
  // Names that only contain a dot, or a store folder's name, stay valid.
  for (const char* name : {"ring.v2", "references2", "my-builds"}) {
    std::string valid = folder.write("valid.yaml", std::string("name: ") + name + "\nscene: " +
                                                       (kCorpus / "scene.yaml").string() +
                                                       "\nmethods:\n  - method: photon_map\n");
    EXPECT_EQ(input_error_message([&] { load_experiment(valid); }), "no error") << name;
  }
}

TEST(ReliabilityFilter, UnknownKnobSuggestsTheClosest) {
  TemporaryFolder folder("filter_terms");
  Experiment experiment = load_experiment(write_valid_experiment(folder));
  auto message_of = [&](const std::string& filter) {
    return input_error_message([&] { check_filter_terms(experiment, filter); });
  };
  std::string message = message_of("method=photon_map,phtons=100000");
  EXPECT_NE(message.find("--filter: key 'phtons=100000'"), std::string::npos) << message;
  EXPECT_NE(message.find("did you mean 'photons'"), std::string::npos) << message;
  EXPECT_NE(message.find("found 'phtons'"), std::string::npos) << message;
  message = message_of("method=photonmap");
  EXPECT_NE(message.find("did you mean 'photon_map'"), std::string::npos) << message;
  message = message_of("variant=defualt");
  EXPECT_NE(message.find("did you mean 'default'"), std::string::npos) << message;
  // Known knobs (set or not), method, variant and label words pass, whether or not they select a run.
  EXPECT_EQ(message_of("photons=1000,k=99,method=photon_map,variant=default,photon"), "no error");
  EXPECT_EQ(message_of(""), "no error");
}

TEST(ReliabilityFilter, RunWithAnUnknownKnobExitsTwoAndWritesNothing) {
  TemporaryFolder folder("filter_run");
  std::string experiment = write_valid_experiment(folder);
  fs::path results = folder.path("results");
  std::string output;
  int code = causticbench_command(
      "run " + shell_quoted(experiment) + " --filter phtons=100000 --results " + shell_quoted(results), output);
  EXPECT_EQ(code, 2) << output;
  EXPECT_NE(output.find("did you mean 'photons'"), std::string::npos) << output;
  EXPECT_FALSE(fs::exists(results)) << output;
}

TEST(ReliabilityThreads, NegativeThreadCountsExitTwoAndWriteNothing) {
  TemporaryFolder folder("threads");
  std::string experiment = write_valid_experiment(folder);
  fs::path results = folder.path("results"), out = folder.path("out");
  std::string output;
  int code =
      causticbench_command("run " + shell_quoted(experiment) + " -t -1 --results " + shell_quoted(results), output);
  EXPECT_EQ(code, 2) << output;
  EXPECT_NE(output.find("--threads"), std::string::npos) << output;
  EXPECT_FALSE(fs::exists(results)) << output;
  code = causticbench_command(
      "render " + shell_quoted(kCorpus / "scene.yaml") + " --threads -2 --out " + shell_quoted(out), output);
  EXPECT_EQ(code, 2) << output;
  EXPECT_NE(output.find("--threads"), std::string::npos) << output;
  EXPECT_FALSE(fs::exists(out)) << output;
}

// OpenImageIO stamped the time of writing into every EXR (capDate), so same-seed runs never compared
// equal with cmp although their pixels did.
TEST(ReliabilityImages, SamePixelsGiveTheSameExrFile) {
  TemporaryFolder folder("exr");
  Image image(3, 2, 3);
  for (size_t pixel = 0; pixel < image.pixel_count(); ++pixel) image.at(pixel, 1) = 0.25f * static_cast<float>(pixel);
  std::string first = folder.path("first.exr").string(), second = folder.path("second.exr").string();
  write_exr(image, first);
  // The header's date has a resolution of one second.
  std::this_thread::sleep_for(std::chrono::milliseconds(1100));
  write_exr(image, second);
  std::string first_bytes = read_text(first), second_bytes = read_text(second);
  EXPECT_TRUE(first_bytes == second_bytes);
  // The attribute is there (OpenImageIO always writes it) with a size of 0 bytes: no date at all.
  const std::string attribute("capDate\0string\0", 15);
  size_t at = first_bytes.find(attribute);
  ASSERT_NE(at, std::string::npos);
  EXPECT_EQ(first_bytes.substr(at + attribute.size(), 4), std::string(4, '\0'));
}
