// Input that used to abort in the tracer or be accepted without a word: degenerate cameras (at any frame,
// after any override), duplicate YAML keys, experiment names that leave their results folder, filters
// that select nothing, negative thread counts, repeated frames, empty metric lists, and EXR files that
// differ only in their date. Each is an input error naming file, line, key, expected and found; on the
// command line, exit code 2 with nothing written.
#include <sys/stat.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>
#include <thread>

#include <fmt/format.h>
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
                                        "reference: {photons_per_pass: 10000, max_passes: 1, target_error: 0}\n"
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

// ---------------------------------------------------------------------------------------------------
// Bounded work before any check: sweeps, file sizes, FIFOs and devices, memory.

// The limit counts exactly: max_runs runs pass, one more is refused (a 2 x 2 sweep on two variants: 8).
TEST(ReliabilityLimits, MaxRunsCountsEveryCombinationOnEveryVariant) {
  TemporaryFolder folder("max_runs");
  auto experiment = [&](int max_runs) {
    return folder.write("sweep.yaml", fmt::format("max_runs: {}\nscene: {}\nvariants: [{{resolution: [8, 8]}}, "
                                                  "{{resolution: [16, 16]}}]\nmethods:\n  - method: photon_map\n"
                                                  "    sweep: {{photons: [1000, 2000], k: [10, 20]}}\n",
                                                  max_runs, (kCorpus / "scene.yaml").string()));
  };
  EXPECT_EQ(input_error_message([&] { EXPECT_EQ(load_experiment(experiment(8)).runs.size(), 8u); }), "no error");
  std::string message = input_error_message([&] { load_experiment(experiment(7)); });
  EXPECT_NE(message.find("at most max_runs = 7 runs"), std::string::npos) << message;
  EXPECT_NE(message.find("found 8 runs up to this entry, 8 of them here: 1 x 2 (photons) x 2 (k) x 2 variants"),
            std::string::npos)
      << message;
}

// A FIFO as a scene blocked the read forever; /dev/zero never ended; a huge file exhausted memory.
TEST(ReliabilityLimits, OnlyRegularFilesOfBoundedSizeAreRead) {
  TemporaryFolder folder("special_files");
  const std::string fifo = folder.path("scene_fifo.yaml").string();
  ASSERT_EQ(mkfifo(fifo.c_str(), 0600), 0);
  std::string output;
  // `timeout` turns a regression (a blocked read) into a failure instead of a hung test.
  int code = run_command("timeout 20 " + std::string(CAUSTICBENCH_BINARY) + " --quiet validate " + fifo, output);
  EXPECT_EQ(code, 2) << output;
  EXPECT_NE(output.find("scene_fifo.yaml: expected a regular file (a scene or experiment), found a FIFO"),
            std::string::npos)
      << output;
  code = run_command("timeout 20 " + std::string(CAUSTICBENCH_BINARY) + " --quiet validate /dev/zero", output);
  EXPECT_EQ(code, 2) << output;
  EXPECT_NE(output.find("/dev/zero: expected a regular file (a scene or experiment), found a device"),
            std::string::npos)
      << output;
  const std::string large = folder.write("large.yaml", "sweep: [" + std::string(kMaximumConfigurationBytes, ' ') + "]\n");
  std::string message = input_error_message([&] { load_experiment(large); });
  EXPECT_NE(message.find("large.yaml: expected a configuration file of at most 4 MiB"), std::string::npos) << message;
  EXPECT_NE(message.find("found 4.0 MiB"), std::string::npos) << message;
}

// --set took hex that the YAML reader refuses, and kept the last of a repeated knob without a word.
TEST(ReliabilityLimits, SetTakesDecimalNumbersAndEachKnobOnce) {
  TemporaryFolder folder("set");
  const std::string scene = shell_quoted(kCorpus / "scene.yaml"), out = shell_quoted(folder.path("out"));
  struct Case {
    std::string arguments, expected;
  };
  for (const Case& item : {Case{"--set photons=0x10", "key 'photon_map.photons': expected an integer, found '0x10'"},
                           Case{"--set max_radius=' 0.1'", "expected auto or a decimal number, found ' 0.1'"},
                           Case{"--set max_radius=infinity", "expected auto or a decimal number, found 'infinity'"},
                           Case{"--set photons=1000 --set photons=2000",
                                "--set: expected each knob once, found 'photons' twice ('photons=1000' and "
                                "'photons=2000')"}}) {
    std::string output;
    int code = causticbench_command("render " + scene + " --method photon_map " + item.arguments + " --out " + out, output);
    EXPECT_EQ(code, 2) << item.arguments << ": " << output;
    EXPECT_NE(output.find(item.expected), std::string::npos) << item.arguments << ": " << output;
    EXPECT_FALSE(fs::exists(folder.path("out"))) << output;
  }
  // What is still a number: signs, a leading point, exponents.
  std::string output;
  EXPECT_EQ(causticbench_command("render " + scene + " --method photon_map --set photons=+1e3 --set max_radius=.5 " +
                                     "--set cone_filter_k=1.5E0 --out " + out, output),
            0)
      << output;
}

// An environment map that cannot be decoded, or holds a NaN, is blamed on the scene line that names it.
TEST(ReliabilityLimits, EnvironmentMapDefectsNameTheSceneLine) {
  TemporaryFolder folder("environment_map");
  Image map(4, 2, 3);
  for (size_t pixel = 0; pixel < map.pixel_count(); ++pixel) map.at(pixel, 0) = 1.0f;
  map.at(1, 2) = std::numeric_limits<float>::quiet_NaN();
  write_exr(map, folder.path("nan.exr").string());
  std::ofstream(folder.path("truncated.exr")) << read_text(folder.path("nan.exr").string()).substr(0, 40);
  // Issue 30, defect 3: finite texels of 3e38 overflowed the sums (NaN pixels, exit 0), and a 1 x 1 black
  // map divided 0 by 0 in its sampling pdf.
  Image huge(4, 2, 3);
  for (size_t pixel = 0; pixel < huge.pixel_count(); ++pixel) huge.at(pixel, 1) = 3e38f;
  write_exr(huge, folder.path("huge.exr").string());
  write_exr(Image(1, 1, 3), folder.path("black.exr").string());
  for (std::string image : {"nan.exr", "truncated.exr", "huge.exr", "black.exr"}) {
    std::string scene = folder.write("scene.yaml", "camera: {position: [0, 2, 3], look_at: [0, 0, 0], resolution: [8, 8]}\n"
                                                   "lights:\n  - {type: environment, image: " + image +
                                                       "}\nobjects:\n  - shape: {type: quad, size: [4, 4]}\n"
                                                       "    material: {type: diffuse, albedo: 0.5}\n");
    std::string message = input_error_message([&] { load_scene(scene); });
    EXPECT_NE(message.find("scene.yaml:3:25: key 'lights[0].image': expected a readable HDR environment map with "
                           "finite texels"),
              std::string::npos)
        << message;
    if (image == "nan.exr") {
      EXPECT_NE(message.find("texel (1, 0) channel 2 is nan"), std::string::npos) << message;
    }
    if (image == "huge.exr") {
      EXPECT_NE(message.find("texel (0, 0) channel 1 is 3e+38 (times scale 1): expected radiance of at most 1e+20"),
                std::string::npos)
          << message;
    }
    if (image == "black.exr") {
      EXPECT_NE(message.find("every texel is black (1 x 1)"), std::string::npos) << message;
    }
  }
}

// A frame that cannot fit in memory is refused with the estimate before any work, for render and run.
TEST(ReliabilityLimits, FramesThatCannotFitInMemoryAreRefusedBeforeAnyWork) {
  TemporaryFolder folder("memory");
  const std::string limit = "CAUSTICBENCH_AVAILABLE_MEMORY=300000000 ";  // 286 MiB: the process base and a bit
  std::string output;
  fs::path out = folder.path("out");
  int code = run_command(limit + CAUSTICBENCH_BINARY + " --quiet render " + shell_quoted(kCorpus / "scene.yaml") +
                             " --method photon_map -r 2048x2048 --out " + shell_quoted(out), output);
  EXPECT_EQ(code, 2) << output;
  EXPECT_NE(output.find("with photon_map at 2048x2048: expected a frame that fits in the available memory (0.3 GiB)"),
            std::string::npos)
      << output;
  EXPECT_NE(output.find("2048x2048 = 4194304 pixels x ("), std::string::npos) << output;
  EXPECT_FALSE(fs::exists(out)) << output;
  // The same frame size fits once the machine has the memory.
  EXPECT_EQ(run_command("CAUSTICBENCH_AVAILABLE_MEMORY=1e12 " + std::string(CAUSTICBENCH_BINARY) + " --quiet render " +
                            shell_quoted(kCorpus / "scene.yaml") + " --method photon_map --set photons=1000 -r 64x64 --out " +
                            shell_quoted(out), output),
            0)
      << output;
  std::string experiment = folder.write("large.yaml", "name: large\nscene: " + (kCorpus / "scene.yaml").string() +
                                                          "\noverrides: {resolution: [4096, 4096]}\nrepetitions: 1\n"
                                                          "methods:\n  - method: photon_map\n");
  fs::path results = folder.path("results");
  code = run_command(limit + CAUSTICBENCH_BINARY + " --quiet run " + experiment + " --results " + shell_quoted(results), output);
  EXPECT_EQ(code, 2) << output;
  EXPECT_NE(output.find("large.yaml: variant default with reference at 4096x4096: expected a frame that fits"),
            std::string::npos)
      << output;
  EXPECT_FALSE(fs::exists(results)) << output;
}

// A write the environment makes fail (a full disk) is an error of its own, not an "internal error".
TEST(ReliabilityLimits, AFailedWriteNamesTheFileAndTheSystemError) {
  TemporaryFolder folder("write_error");
  fs::path out = folder.path("out");
  std::string output;
  int code = run_command("CAUSTICBENCH_FAULT_INJECT=fail@caustic.exr " + std::string(CAUSTICBENCH_BINARY) +
                             " --quiet render " + shell_quoted(kCorpus / "scene.yaml") +
                             " --method photon_map --set photons=1000 --out " + shell_quoted(out), output);
  EXPECT_EQ(code, 1) << output;
  EXPECT_NE(output.find("error: cannot write " + (out / "caustic.exr").string()), std::string::npos) << output;
  EXPECT_NE(output.find("No space left on device (ENOSPC)"), std::string::npos) << output;
  EXPECT_EQ(output.find("internal error"), std::string::npos) << output;
  // Nothing was written, so the folder the render made is gone too (no temporary file, no empty folder).
  EXPECT_FALSE(fs::exists(out)) << output;
  // Into a folder that existed, a later file's failure keeps what was written and no temporary file.
  fs::create_directories(out);
  code = run_command("CAUSTICBENCH_FAULT_INJECT=fail@composite.png " + std::string(CAUSTICBENCH_BINARY) +
                         " --quiet render " + shell_quoted(kCorpus / "scene.yaml") +
                         " --method photon_map --set photons=1000 --out " + shell_quoted(out), output);
  EXPECT_EQ(code, 1) << output;
  EXPECT_TRUE(fs::exists(out / "caustic.exr")) << output;
  EXPECT_FALSE(fs::exists(out / "composite.png")) << output;
  for (const auto& entry : fs::directory_iterator(out)) EXPECT_FALSE(is_partial_file_name(entry.path().filename().string()));
}

// --results that cannot be a results folder (a file, a file above it, a symbolic-link loop) used to
// fail with exit code 1 after the work had started; now exit code 2 first, naming the path and reason.
TEST(ReliabilityLimits, ResultsFolderProblemsAreInputErrors) {
  TemporaryFolder folder("results_folder");
  std::string experiment = write_valid_experiment(folder);
  folder.write("a_file", "not a folder\n");
  fs::create_symlink(folder.path("loop_b"), folder.path("loop_a"));
  fs::create_symlink(folder.path("loop_a"), folder.path("loop_b"));
  struct Case {
    fs::path results;
    std::string expected;
  };
  for (const Case& item : {Case{folder.path("a_file"), "a_file', which is a file"},
                           Case{folder.path("a_file") / "results", "a_file/results': Not a directory (ENOTDIR)"},
                           Case{folder.path("loop_a"), "Too many levels of symbolic links (ELOOP)"}}) {
    std::string output;
    int code = causticbench_command("run " + shell_quoted(experiment) + " --results " + shell_quoted(item.results), output);
    EXPECT_EQ(code, 2) << output;
    EXPECT_NE(output.find("--results: expected a folder to write results into, found '"), std::string::npos) << output;
    EXPECT_NE(output.find(item.expected), std::string::npos) << output;
  }
  EXPECT_EQ(read_text(folder.path("a_file").string()), "not a folder\n");
}

// Issue 30, defect 12: --build-cache is checked like --results before any work. A file there used to give
// "internal error: filesystem error" (exit 1) after the build was computed.
TEST(ReliabilityLimits, BuildCacheFolderProblemsAreInputErrors) {
  TemporaryFolder folder("build_cache_folder");
  folder.write("a_file", "not a folder\n");
  for (const fs::path& cache : {folder.path("a_file"), folder.path("a_file") / "builds"}) {
    std::string output;
    int code = causticbench_command("render " + shell_quoted(kCorpus / "scene.yaml") + " --method photon_map --set photons=1000 "
                                    "--out " + shell_quoted(folder.path("out")) + " --build-cache " + shell_quoted(cache),
                                    output);
    EXPECT_EQ(code, 2) << output;
    EXPECT_NE(output.find("--build-cache: expected a folder to write stored builds into, found '"), std::string::npos) << output;
    EXPECT_TRUE(is_missing_or_empty(folder.path("out"))) << "nothing rendered or written";
  }
  EXPECT_EQ(read_text(folder.path("a_file").string()), "not a folder\n");
}
