// A reference with no caustic in view: the rule that finds it (metrics/caustic_presence.h), the shipped
// scene that has one (a paraboloid dish turned over under light from above), the check that stops
// `causticbench run` with exit code 2 before any method runs, the key that lets an extremes experiment
// run anyway (its runs reported as "empty reference"), and the warning of `causticbench render`.
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "core/direct_lighting.h"
#include "core/image.h"
#include "experiments/experiment.h"
#include "metrics/caustic_presence.h"
#include "tests/test_support.h"

using namespace causticbench;
using causticbench::testing::run_command;
namespace fs = std::filesystem;

namespace {

const std::string kTurnedOverDish = std::string(CAUSTICBENCH_SCENES) + "/paraboloid_turned_over.yaml";

// A temporary folder for experiment files and their results.
class Folder : public causticbench::testing::TemporaryFolder {
 public:
  explicit Folder(const std::string& name) : TemporaryFolder("empty_" + name) {}
};

std::string read_text(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

std::vector<std::string> stored_runs(const fs::path& runs) {
  std::vector<std::string> keys;
  if (!fs::is_directory(runs)) return keys;
  for (const auto& entry : fs::directory_iterator(runs)) keys.push_back(entry.path().filename().string());
  return keys;
}

// The turned-over dish at 32 x 32 with a cheap reference and one pinhole run; `extra` is appended.
std::string dish_experiment(const std::string& extra = "") {
  return "name: turned_over\nscene: " + kTurnedOverDish + R"(
overrides: {resolution: [32, 32]}
reference: {photons_per_pass: 20000, max_passes: 2, target_error: 0}
repetitions: 1
methods:
  - method: pinhole
    frame: {samples: 100, environment_resolution: 16}
)" + extra;
}

int run_cli(const std::string& arguments, std::string& output) {
  return run_command(std::string(CAUSTICBENCH_BINARY) + " " + arguments, output);
}

Image uniform(int width, int height, float value) { return Image(width, height, 3, value); }

}  // namespace

// The rule itself: empty when no receiver is in view, when E_c sums to 0, and up to the stated fraction
// of the direct irradiance; present above it, and whenever there is caustic light but no direct light.
TEST(CausticPresence, RuleAndThreshold) {
  const std::vector<uint8_t> receivers = {1, 1, 0, 1};
  const Image direct = uniform(4, 1, 2.0f);  // 3 receivers: direct sum 6
  EXPECT_TRUE(measure_caustic_presence(uniform(4, 1, 0.0f), direct, receivers).empty());
  EXPECT_TRUE(measure_caustic_presence(uniform(4, 1, 1.0f), direct, {0, 0, 0, 0}).empty()) << "no receiver in view";

  // Caustic light on one receiver only: its channel mean is the whole sum.
  auto one_pixel = [](float value) {
    Image image = uniform(4, 1, 0.0f);
    image.set_rgb(0, Color(value));
    return image;
  };
  const double threshold = kEmptyCausticFraction * 6.0;
  EXPECT_TRUE(measure_caustic_presence(one_pixel(static_cast<float>(0.999 * threshold)), direct, receivers).empty());
  EXPECT_FALSE(measure_caustic_presence(one_pixel(static_cast<float>(1.001 * threshold)), direct, receivers).empty());
  // Light on an unmasked pixel does not count.
  Image off_receiver = uniform(4, 1, 0.0f);
  off_receiver.set_rgb(2, Color(100.0f));
  EXPECT_TRUE(measure_caustic_presence(off_receiver, direct, receivers).empty());
  // No direct light (everything in shadow) but caustic light: present.
  EXPECT_FALSE(measure_caustic_presence(one_pixel(1e-3f), uniform(4, 1, 0.0f), receivers).empty());

  CausticPresence presence = measure_caustic_presence(uniform(4, 1, 0.0f), direct, receivers);
  EXPECT_EQ(presence.receiver_pixels, 3u);
  EXPECT_EQ(presence.caustic_sum, 0.0);
  EXPECT_DOUBLE_EQ(presence.direct_sum, 6.0);
  EXPECT_NE(presence.describe().find("3 receiver pixels"), std::string::npos) << presence.describe();
}

// The shipped test scene: the reference of the turned-over dish is exactly 0 over a floor in full sun,
// while the upright dish (paraboloid.yaml) under the same light has its caustic.
TEST(CausticPresence, TurnedOverDishHasNoCausticInView) {
  auto presence_of = [](const std::string& file) {
    Scene scene = load_scene(file);
    set_resolution(scene, 48, 48);
    FrameResult result = causticbench::testing::render(
        scene, "reference", {"photons_per_pass=40000", "max_passes=2", "target_error=0", "max_seconds=0"});
    PosedFrame posed(scene, 0);
    Image direct = direct_irradiance(posed.tracer, posed.gbuffer, 4, 1);
    return measure_caustic_presence(result.caustic, direct, result.gbuffer.receiver);
  };
  CausticPresence dish = presence_of(kTurnedOverDish);
  EXPECT_GT(dish.receiver_pixels, 1000u) << "the floor fills most of the view";
  EXPECT_GT(dish.direct_sum, 1000.0) << "and the sun is on it";
  EXPECT_EQ(dish.caustic_sum, 0.0) << "every reflected ray goes to the sky";
  EXPECT_TRUE(dish.empty());

  CausticPresence upright = presence_of(std::string(CAUSTICBENCH_SCENES) + "/paraboloid.yaml");
  EXPECT_FALSE(upright.empty()) << upright.describe();
}

// `causticbench run` on the turned-over dish stops before any method runs: exit code 2, the scene, the
// variant, the frame, the measured sums and what to check; nothing in the experiment's folder, the
// reference kept.
TEST(EmptyReferenceRun, StopsWithExitCode2AndStoresNoRun) {
  Folder folder("stops");
  std::string experiment = folder.write("dish.yaml", dish_experiment());
  std::string results = folder.path("results");
  std::string output;
  int code = run_cli("run " + experiment + " --results " + results, output);
  EXPECT_EQ(code, 2) << output;
  for (const char* expected : {"paraboloid_turned_over.yaml", "variant default", "frame 0", "E_c summed over its",
                               "is 0 W/m^2", "direct irradiance", "check that the camera sees",
                               "the lights reach the specular", "empty_reference_expected: true", "No run was started"})
    EXPECT_NE(output.find(expected), std::string::npos) << "missing '" << expected << "' in:\n" << output;
  EXPECT_FALSE(fs::exists(results + "/turned_over")) << "nothing is written into the experiment's folder";
  Experiment loaded = load_experiment(experiment);
  EXPECT_TRUE(fs::is_regular_file(results + "/references/" + loaded.variants[0].reference_key + "/frame_0000.exr"))
      << "the reference is valid data and stays cached";
}

// With several variants every reference is checked before the first run: an empty second variant (a
// camera that sees only sky, so no receiver pixel) stops a --force rerun before the first variant's run
// is replaced; what was stored stays as it was.
TEST(EmptyReferenceRun, EveryVariantIsCheckedBeforeAnyRunAndStoredRunsStay) {
  Folder folder("variants");
  std::string scene = causticbench::testing::kSmallGlassSphere;
  scene = causticbench::testing::replace_once(scene, "resolution: [40, 40]", "resolution: [24, 24]");
  folder.write("scene.yaml", scene);
  const std::string base = R"(name: two_views
scene: scene.yaml
reference: {photons_per_pass: 20000, max_passes: 2, target_error: 0}
repetitions: 1
methods:
  - method: photon_map
    build: {photons: 2000}
)";
  std::string results = folder.path("results");
  std::string output;
  std::string good = folder.write("good.yaml", base + "variants: [{name: good}]\n");
  ASSERT_EQ(run_cli("run " + good + " --results " + results + " --no-report", output), 0) << output;
  fs::path runs = fs::path(results) / "two_views" / "runs";
  std::vector<std::string> before = stored_runs(runs);
  ASSERT_EQ(before.size(), 1u) << output;
  const std::string record_before = read_text(runs / before[0] / "record.json");
  const std::string experiment_before = read_text(fs::path(results) / "two_views" / "experiment.json");

  std::string both = folder.write(
      "both.yaml", base + "variants: [{name: good}, {name: sky, camera: {look_at: [0, 10, 0]}}]\n");
  int code = run_cli("run " + both + " --results " + results + " --force", output);
  EXPECT_EQ(code, 2) << output;
  EXPECT_NE(output.find("variant sky"), std::string::npos) << output;
  EXPECT_NE(output.find("no receiver pixel"), std::string::npos) << output;
  EXPECT_EQ(stored_runs(runs), before) << "no run of the empty variant is stored";
  EXPECT_EQ(read_text(runs / before[0] / "record.json"), record_before) << "the first variant's run did not run again";
  EXPECT_EQ(read_text(fs::path(results) / "two_views" / "experiment.json"), experiment_before);
}

// An extremes experiment that says so runs, and its runs are stored and reported as "empty reference":
// no metric but nonfinite_pixels and max_error has a value, the report scores nothing. The key leaves run keys alone.
TEST(EmptyReferenceRun, ExpectedEmptyReferenceRunsAndIsReportedAsSuch) {
  Folder folder("expected");
  std::string plain = folder.write("plain.yaml", dish_experiment());
  std::string expected = folder.write("dish.yaml", dish_experiment("empty_reference_expected: true\n"));
  std::set<std::string> plain_keys, expected_keys;
  for (const RunSpec& run : load_experiment(plain).runs) plain_keys.insert(run.key);
  for (const RunSpec& run : load_experiment(expected).runs) expected_keys.insert(run.key);
  EXPECT_EQ(plain_keys, expected_keys) << "the key judges runs, it does not change what they compute";

  std::string results = folder.path("results");
  std::string output;
  ASSERT_EQ(run_cli("run " + expected + " --results " + results, output), 0) << output;
  EXPECT_NE(output.find("1 run now, 0 failed"), std::string::npos) << output;
  EXPECT_NE(output.find("stored as \"empty reference\""), std::string::npos) << output;

  fs::path experiment_folder = fs::path(results) / "turned_over";
  std::vector<std::string> keys = stored_runs(experiment_folder / "runs");
  ASSERT_EQ(keys.size(), 1u);
  nlohmann::json record = nlohmann::json::parse(read_text(experiment_folder / "runs" / keys[0] / "record.json"));
  EXPECT_EQ(record["status"], "ok") << record["error"];
  EXPECT_EQ(record["empty_reference"]["frames"], nlohmann::json::array({0}));
  EXPECT_NE(record["empty_reference"]["reason"].get<std::string>().find("is 0 W/m^2"), std::string::npos);
  // Only the two values that judge the method alone: its non-finite pixels, and max_error, which against
  // an empty reference is the brightest E_c it gave (pinhole does not model that the dish's mirror faces
  // away from the light's side of the floor, so it is not 0 here).
  EXPECT_EQ(record["metrics"].size(), 2u) << record["metrics"];
  EXPECT_EQ(record["metrics"]["nonfinite_pixels"], 0.0) << record["metrics"];
  ASSERT_TRUE(record["metrics"].contains("max_error")) << record["metrics"];
  // Against nothing, max_error is the stored frame's brightest value (zero off the receivers), and that is
  // not 0 here.
  const Image stored = read_exr((experiment_folder / "runs" / keys[0] / "frame_0000.exr").string());
  float brightest = 0.0f;
  for (float value : stored.values()) brightest = std::max(brightest, value);
  EXPECT_GT(brightest, 0.0f);
  EXPECT_DOUBLE_EQ(record["metrics"]["max_error"].get<double>(), static_cast<double>(brightest));
  for (const char* metric : {"mse", "rmse", "psnr", "ssim", "relmse", "energy_ratio"}) {
    ASSERT_TRUE(record["metrics_undefined"].contains(metric)) << metric;
    EXPECT_EQ(record["metrics_undefined"][metric].get<std::string>().rfind("empty reference: ", 0), 0u) << metric;
    EXPECT_TRUE(record["frames"][0]["metrics_undefined"].contains(metric)) << metric;
  }
  EXPECT_GT(record["timings"]["frame_ms_median"].get<double>(), 0.0) << "timings are still measured";

  std::string markdown = read_text(experiment_folder / "report.md");
  EXPECT_NE(markdown.find("(empty reference)"), std::string::npos) << markdown;
  EXPECT_NE(markdown.find("undefined: empty reference: "), std::string::npos) << markdown;
  EXPECT_NE(markdown.find("1 run against an empty reference"), std::string::npos) << markdown;
  EXPECT_EQ(markdown.find("Best relmse"), std::string::npos) << "nothing is best against nothing";
  EXPECT_NE(markdown.find("| \u2014 [1] |"), std::string::npos) << "metric cells are empty with a footnote";
  nlohmann::json results_json = nlohmann::json::parse(read_text(experiment_folder / "results.json"));
  EXPECT_TRUE(results_json["pareto_front"]["overall"].empty()) << results_json["pareto_front"];
}

// `causticbench render --method reference` warns (and still writes its files) on the turned-over dish,
// by the same rule; a scene with a caustic in view gets no warning.
TEST(EmptyReferenceRender, ReferenceWarnsWhenNothingIsInView) {
  Folder folder("render");
  const std::string knobs =
      " --method reference --set photons_per_pass=20000 --set max_passes=2 --set target_error=0"
      " --resolution 24x24 --direct-samples 4";
  std::string output;
  int code = run_cli("render " + kTurnedOverDish + knobs + " --out " + folder.path("dish"), output);
  EXPECT_EQ(code, 0) << output;
  EXPECT_NE(output.find("warning: the reference of scene " + kTurnedOverDish + " has no caustic in view on frame 0"),
            std::string::npos)
      << output;
  EXPECT_NE(output.find("check that the camera sees"), std::string::npos) << output;
  EXPECT_TRUE(fs::is_regular_file(folder.path("dish") + "/caustic.exr"));

  code = run_cli("render " + std::string(CAUSTICBENCH_SCENES) + "/tiny.yaml" + knobs + " --out " + folder.path("tiny"),
                 output);
  EXPECT_EQ(code, 0) << output;
  EXPECT_EQ(output.find("warning:"), std::string::npos) << output;
}
