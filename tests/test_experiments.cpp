// Experiments: sweep expansion, stable run keys, strict validation, claims and filters (the runner's
// shards, resume and an end-to-end run: test_runner.cpp).
#include <fcntl.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <thread>

#include <gtest/gtest.h>

#include "experiments/experiment.h"
#include "experiments/runner.h"
#include "tests/experiment_test_support.h"
#include "tests/test_support.h"

using namespace causticbench;
using causticbench::testing::run_command;
namespace fs = std::filesystem;
using nlohmann::json;

using namespace causticbench::experiment_testing;

TEST(Sweep, CartesianZipAndFixed) {
  auto entry = [](const std::string& text) { return ParamDict::Entry{text, SourceLocation{"test", 1, 1}}; };
  KnobAssignment fixed{{"seed", entry("3")}};
  auto runs = expand_sweep(fixed, {{"photons", {entry("10"), entry("20")}}, {"k", {entry("1"), entry("2"), entry("3")}}},
                           {{"a", {entry("x"), entry("y")}}, {"b", {entry("u"), entry("v")}}});
  ASSERT_EQ(runs.size(), 2u * 2u * 3u);
  std::set<std::string> combinations;
  for (const KnobAssignment& run : runs) {
    EXPECT_EQ(run.at("seed").text, "3");
    // zip pairs a with b, never crosses them
    EXPECT_TRUE((run.at("a").text == "x" && run.at("b").text == "u") || (run.at("a").text == "y" && run.at("b").text == "v"));
    combinations.insert(run.at("a").text + run.at("photons").text + run.at("k").text);
  }
  EXPECT_EQ(combinations.size(), 12u);
  EXPECT_EQ(expand_sweep(fixed, {}, {}).size(), 1u);
}

TEST(Experiment, ExpandsAndKeysAreStableAcrossKeyOrder) {
  ExperimentFolder folder("experiment_keys");
  Experiment first = load_experiment(folder.write("a.yaml", kExperiment));
  ASSERT_EQ(first.runs.size(), 6u);
  EXPECT_EQ(first.runs[0].params.integer("photons"), 1000);
  EXPECT_EQ(first.runs[0].render.real("max_radius"), 0.3);
  EXPECT_EQ(first.runs[0].swept.size(), 2u);
  // The same experiment with every map in another order, numbers written differently.
  Experiment reordered = load_experiment(folder.write("b.yaml", R"(methods:
  - sweep:
      k: [10, 20, 30]
      photons: [1e3, 2000]
    render: {max_radius: 0.30}
    method: photon_map
repetitions: 1
reference: {target_error: 0, max_passes: 3, photons_per_pass: 100000}
scene: scene.yaml
name: tiny
)"));
  std::set<std::string> keys_a, keys_b;
  for (const RunSpec& run : first.runs) keys_a.insert(run.key);
  for (const RunSpec& run : reordered.runs) keys_b.insert(run.key);
  EXPECT_EQ(keys_a, keys_b);
  EXPECT_EQ(keys_a.size(), 6u);
  EXPECT_EQ(first.variants.front().reference_key, reordered.variants.front().reference_key);
  // A different knob value is a different run.
  Experiment changed = load_experiment(folder.write("c.yaml", replace(kExperiment, "max_radius: 0.3", "max_radius: 0.4")));
  EXPECT_EQ(changed.runs.size(), 6u);
  EXPECT_EQ(keys_a.count(changed.runs[0].key), 0u);
  EXPECT_EQ(first.variants.front().reference_key, changed.variants.front().reference_key);
}

TEST(Experiment, RejectsBadInputWithFileAndLine) {
  ExperimentFolder folder("experiment_errors");
  std::string message = error_of(folder, replace(kExperiment, "repetitions: 1", "repetitons: 1"));
  EXPECT_NE(message.find("bad.yaml:4:1"), std::string::npos) << message;
  EXPECT_NE(message.find("did you mean 'repetitions'"), std::string::npos) << message;
  message = error_of(folder, replace(kExperiment, "      k: [10, 20, 30]", "      kk: [10, 20, 30]"));
  EXPECT_NE(message.find("bad.yaml:10:"), std::string::npos) << message;
  EXPECT_NE(message.find("unknown parameter 'kk'"), std::string::npos) << message;
  message = error_of(folder, replace(kExperiment, "render: {max_radius: 0.3}", "render: {photons: 5}"));
  EXPECT_NE(message.find("bad.yaml:7:"), std::string::npos) << message;
  EXPECT_NE(message.find("is a build knob"), std::string::npos) << message;
  message = error_of(folder, replace(kExperiment, "      k: [10, 20, 30]", "      k: [10, 0, 30]"));
  EXPECT_NE(message.find("bad.yaml:10:"), std::string::npos) << message;
  EXPECT_NE(message.find("photon_map.k"), std::string::npos) << message;
  message = error_of(folder, replace(kExperiment, "method: photon_map", "method: photonmap"));
  EXPECT_NE(message.find("did you mean 'photon_map'"), std::string::npos) << message;
  message = error_of(folder, replace(kExperiment, "    sweep:", "    zip: {seed: [1, 2, 3]}\n    sweep:"));
  EXPECT_EQ(message, "no error");
  message = error_of(folder, replace(kExperiment, "    sweep:", "    zip: {seed: [1, 2, 3], cone_filter_k: [1.1, 1.2]}\n    sweep:"));
  EXPECT_NE(message.find("a list of 3 values"), std::string::npos) << message;
  message = error_of(folder, replace(kExperiment, "scene: scene.yaml", "scene: missing.yaml"));
  EXPECT_NE(message.find("bad.yaml:2:"), std::string::npos) << message;
  message = error_of(folder, replace(kExperiment, "repetitions: 1", "repetitions: 1\nframes: [3]"));
  EXPECT_NE(message.find("frame index in 0 .. 0"), std::string::npos) << message;
  message = error_of(folder, replace(kExperiment, "repetitions: 1", "repetitions: 1\nmetrics: [rmse, psnrr]"));
  EXPECT_NE(message.find("did you mean 'psnr'"), std::string::npos) << message;
}

TEST(Experiment, VariantsMultiplyRunsWithTheirOwnReference) {
  ExperimentFolder folder("experiment_variants");
  Experiment plain = load_experiment(folder.write("plain.yaml", kExperiment));
  ASSERT_EQ(plain.variants.size(), 1u);
  EXPECT_EQ(plain.variants[0].name, "default");
  std::string text = replace(kExperiment, "repetitions: 1", R"(repetitions: 1
overrides: {camera: {fov_degrees: 40}}
variants:
  - {resolution: [16, 16]}
  - {resolution: [32, 24]}
  - {name: wide, camera: {fov_degrees: 60}})");
  Experiment varied = load_experiment(folder.write("varied.yaml", text));
  ASSERT_EQ(varied.variants.size(), 3u);
  EXPECT_EQ(varied.variants[0].name, "16x16");
  EXPECT_EQ(varied.variants[1].name, "32x24");
  EXPECT_EQ(varied.variants[2].name, "wide");
  // Each variant is the base overrides with its own on top.
  EXPECT_EQ(varied.variants[1].scene.camera.width, 32);
  EXPECT_EQ(varied.variants[1].scene.camera.height, 24);
  EXPECT_DOUBLE_EQ(varied.variants[1].scene.camera.fov_degrees, 40.0);
  EXPECT_DOUBLE_EQ(varied.variants[2].scene.camera.fov_degrees, 60.0);
  EXPECT_EQ(varied.variants[2].scene.camera.width, 24);  // the scene's own resolution
  // Every method entry runs on every variant, each with its own key and reference.
  EXPECT_EQ(varied.runs.size(), 3 * plain.runs.size());
  std::set<std::string> keys, references;
  for (const RunSpec& run : varied.runs) keys.insert(run.key);
  for (const SceneVariant& variant : varied.variants) references.insert(variant.reference_key);
  EXPECT_EQ(keys.size(), varied.runs.size());
  EXPECT_EQ(references.size(), 3u);
  // A variant with no overrides of its own is the plain experiment: same keys, same reference.
  Experiment same = load_experiment(folder.write("same.yaml", replace(kExperiment, "repetitions: 1", "repetitions: 1\nvariants: [{name: only}]")));
  EXPECT_EQ(same.variants[0].reference_key, plain.variants[0].reference_key);
  EXPECT_EQ(same.runs[0].key, plain.runs[0].key);
  // Filters select by variant.
  size_t wide = 0;
  for (const RunSpec& run : varied.runs) wide += run_matches_filter(varied, run, "variant=wide,k=20") ? 1 : 0;
  EXPECT_EQ(wide, 2u);
  // Bad variants: an unknown key, two of the same name, an empty list.
  std::string message = error_of(folder, replace(kExperiment, "repetitions: 1", "repetitions: 1\nvariants:\n  - {resolutoin: [8, 8]}"));
  EXPECT_NE(message.find("bad.yaml:6:"), std::string::npos) << message;
  EXPECT_NE(message.find("did you mean 'resolution'"), std::string::npos) << message;
  message = error_of(folder, replace(kExperiment, "repetitions: 1", "repetitions: 1\nvariants:\n  - {resolution: [8, 8]}\n  - {resolution: [8, 8]}"));
  EXPECT_NE(message.find("a second variant named '8x8'"), std::string::npos) << message;
  message = error_of(folder, replace(kExperiment, "repetitions: 1", "repetitions: 1\nvariants:\n  - {name: a, resolution: [8, 8]}\n  - {name: b, resolution: [8, 8]}"));
  EXPECT_NE(message.find("the same overrides as variant 'a'"), std::string::npos) << message;
  EXPECT_NE(message.find("bad.yaml:7:"), std::string::npos) << message;
  message = error_of(folder, replace(kExperiment, "repetitions: 1", "repetitions: 1\nvariants: []"));
  EXPECT_NE(message.find("a non-empty list"), std::string::npos) << message;
}

// A method entry's `variants` runs it on those variants only (a per-object setting where the variants are
// objects), with the keys it would have had on them; a paper row's `variant` picks one variant's runs.
TEST(Experiment, MethodEntryRunsOnTheVariantsItNames) {
  ExperimentFolder folder("experiment_entry_variants");
  const std::string two = replace(kExperiment, "repetitions: 1",
                                  "repetitions: 1\nvariants: [{name: small, resolution: [8, 8]}, {name: large, resolution: [16, 16]}]");
  const Experiment all = load_experiment(folder.write("all.yaml", two));
  ASSERT_EQ(all.runs.size(), 12u);
  const Experiment large = load_experiment(folder.write("large.yaml", replace(two, "    render:", "    variants: [large]\n    render:")));
  ASSERT_EQ(large.runs.size(), 6u);
  std::set<std::string> keys_on_large;
  for (const RunSpec& run : all.runs)
    if (all.variants[run.variant].name == "large") keys_on_large.insert(run.key);
  for (const RunSpec& run : large.runs) {
    EXPECT_EQ(large.variants[run.variant].name, "large");
    EXPECT_TRUE(keys_on_large.count(run.key)) << "the same run, the same key";
  }
  // An unknown or repeated name, an empty list.
  std::string message = error_of(folder, replace(two, "    render:", "    variants: [lareg]\n    render:"));
  EXPECT_NE(message.find("did you mean 'large'"), std::string::npos) << message;
  EXPECT_NE(message.find("bad.yaml:8:"), std::string::npos) << message;
  message = error_of(folder, replace(two, "    render:", "    variants: [large, large]\n    render:"));
  EXPECT_NE(message.find("'large' again"), std::string::npos) << message;
  message = error_of(folder, replace(two, "    render:", "    variants: []\n    render:"));
  EXPECT_NE(message.find("a non-empty list of variant names"), std::string::npos) << message;
  // max_runs counts the entry's variants only: 6 runs fit under 6.
  EXPECT_NO_THROW(load_experiment(folder.write("max.yaml", replace(replace(two, "    render:", "    variants: [large]\n    render:"),
                                                                    "repetitions: 1", "repetitions: 1\nmax_runs: 6"))));
  // A paper row may match a variant by name, beside knobs.
  const Experiment paper = load_experiment(folder.write(
      "paper.yaml", two + "paper:\n  title: t\n  columns: [frame_ms]\n  rows:\n"
                          "    - {method: photon_map, match: {variant: large, photons: 1000}, values: {frame_ms: 3}}\n"));
  EXPECT_EQ(paper.report.paper.at("rows").at(0).at("match").at("variant"), "large");
  EXPECT_EQ(paper.report.paper.at("rows").at(0).at("match").at("photons"), 1000);
  // ... and a name that is no variant is refused where it stands, with the closest one.
  message = error_of(folder, two + "paper:\n  title: t\n  columns: [frame_ms]\n  rows:\n"
                                   "    - {method: photon_map, match: {variant: lareg}, values: {frame_ms: 3}}\n");
  EXPECT_NE(message.find("one of the experiment's variants (small, large)"), std::string::npos) << message;
  EXPECT_NE(message.find("did you mean 'large'"), std::string::npos) << message;
  EXPECT_NE(message.find("bad.yaml:"), std::string::npos) << message;
}

// A variant may name a scene file of its own (an extremes or capability case): it starts from that
// file, the base overrides apply to it, its content enters the reference's and the runs' keys, and it is
// named after the file unless it says otherwise.
TEST(Experiment, VariantsWithTheirOwnScene) {
  ExperimentFolder folder("experiment_variant_scenes");
  folder.write("denser.yaml", causticbench::testing::replace_once(causticbench::testing::kSmallGlassSphere,
                                                                  "resolution: [40, 40]", "resolution: [20, 20]"));
  Experiment plain = load_experiment(folder.write("plain.yaml", kExperiment));
  std::string text = replace(kExperiment, "repetitions: 1", R"(repetitions: 1
overrides: {camera: {fov_degrees: 40}}
variants:
  - {name: base}
  - {scene: denser.yaml}
  - {name: denser_wide, scene: denser.yaml, camera: {fov_degrees: 60}})");
  Experiment varied = load_experiment(folder.write("varied.yaml", text));
  ASSERT_EQ(varied.variants.size(), 3u);
  EXPECT_EQ(varied.variants[1].name, "denser");
  EXPECT_EQ(varied.variants[1].scene.camera.width, 20);            // its own file
  EXPECT_DOUBLE_EQ(varied.variants[1].scene.camera.fov_degrees, 40.0);  // the base overrides on it
  EXPECT_DOUBLE_EQ(varied.variants[2].scene.camera.fov_degrees, 60.0);
  EXPECT_NE(varied.variants[1].scene_hash, varied.variants[0].scene_hash);
  EXPECT_EQ(varied.variants[0].scene_hash, varied.scene_hash);
  EXPECT_NE(varied.variants[1].scene_path.find("denser.yaml"), std::string::npos);
  std::set<std::string> references;
  for (const SceneVariant& variant : varied.variants) references.insert(variant.reference_key);
  EXPECT_EQ(references.size(), 3u);
  std::set<std::string> keys;
  for (const RunSpec& run : varied.runs) keys.insert(run.key);
  EXPECT_EQ(keys.size(), 3 * plain.runs.size());
  // The same scene text under another file name is the same variant: content, not path, is keyed.
  folder.write("copy.yaml", causticbench::testing::replace_once(causticbench::testing::kSmallGlassSphere,
                                                                "resolution: [40, 40]", "resolution: [24, 24]"));
  Experiment copied = load_experiment(folder.write("copied.yaml", replace(kExperiment, "repetitions: 1",
                                                                          "repetitions: 1\nvariants: [{scene: copy.yaml}]")));
  EXPECT_EQ(copied.runs[0].key, plain.runs[0].key);
  EXPECT_EQ(copied.variants[0].reference_key, plain.variants[0].reference_key);
  // A missing scene file names the variant's key; two variants on the same scene text with the same
  // overrides are one.
  std::string message = error_of(folder, replace(kExperiment, "repetitions: 1", "repetitions: 1\nvariants:\n  - {scene: nowhere.yaml}"));
  EXPECT_NE(message.find("bad.yaml:6:"), std::string::npos) << message;
  EXPECT_NE(message.find("variants[0].scene"), std::string::npos) << message;
  EXPECT_NE(message.find("which does not exist"), std::string::npos) << message;
  message = error_of(folder, replace(kExperiment, "repetitions: 1",
                                     "repetitions: 1\nvariants:\n  - {name: a, scene: denser.yaml}\n  - {name: b, scene: denser.yaml}"));
  EXPECT_NE(message.find("the same overrides as variant 'a'"), std::string::npos) << message;
  // Frames the variant's scene does not have.
  folder.write("animated.yaml", causticbench::testing::replace_once(causticbench::testing::kSmallGlassSphere, "camera:",
                                                                    "frames: 3\ncamera:"));
  message = error_of(folder, replace(replace(kExperiment, "scene: scene.yaml", "scene: animated.yaml"), "repetitions: 1",
                                     "repetitions: 1\nframes: [0, 2]\nvariants: [{name: a}, {scene: scene.yaml}]"));
  EXPECT_NE(message.find("variant 'scene'"), std::string::npos) << message;
}

// Every shipped experiment file validates (scene, methods, knobs, paper block, claims).
TEST(Experiment, ShippedExperimentsValidate) {
  int count = 0;
  for (const auto& entry : fs::directory_iterator(std::string(CAUSTICBENCH_SCENES) + "/../experiments")) {
    if (entry.path().extension() != ".yaml") continue;
    EXPECT_NO_THROW(load_experiment(entry.path().string())) << entry.path();
    ++count;
  }
  EXPECT_GE(count, 7);
}

TEST(Experiment, ClaimsAreValidated) {
  ExperimentFolder folder("experiment_claims");
  std::string good = std::string(kExperiment) + R"(claims:
  - {text: more photons help, kind: better, metric: relmse, run: photons=2000, than: photons=1000}
  - {text: linear time, kind: linear, x: photons, y: render_ms, among: method=photon_map}
  - {text: same error, kind: same, metric: relmse, run: photons=2000, than: photons=1000, relative_tolerance: 0.1}
  - {text: cheap, kind: ratio, y: render_ms, run: photons=2000, than: photons=1000, at_most: 3}
)";
  Experiment experiment = load_experiment(folder.write("good.yaml", good));
  ASSERT_EQ(experiment.report.claims.size(), 4u);
  EXPECT_EQ(experiment.report.claims[1]["min_r2"].get<double>(), 0.98);
  EXPECT_EQ(experiment.report.claims[2]["relative_tolerance"].get<double>(), 0.1);
  EXPECT_EQ(experiment.report.claims[2]["absolute_tolerance"].get<double>(), 0.0) << "unstated: 0";
  EXPECT_EQ(experiment.report.claims[3]["at_most"].get<double>(), 3.0);
  std::string message = error_of(folder, replace(good, "metric: relmse", "metric: relmes"));
  EXPECT_NE(message.find("did you mean 'relmse'"), std::string::npos) << message;
  message = error_of(folder, replace(good, "kind: linear", "kind: quadratic"));
  EXPECT_NE(message.find("one of best, better, same, linear, ratio"), std::string::npos) << message;
  // `same` needs a tolerance, a non-negative one.
  message = error_of(folder, replace(good, ", relative_tolerance: 0.1", ""));
  EXPECT_NE(message.find("a relative_tolerance or an absolute_tolerance"), std::string::npos) << message;
  message = error_of(folder, replace(good, "relative_tolerance: 0.1", "absolute_tolerance: -1"));
  EXPECT_NE(message.find("absolute_tolerance"), std::string::npos) << message;
  message = error_of(folder, replace(good, ", at_most: 3}", "}"));
  EXPECT_NE(message.find("at_most"), std::string::npos) << "a ratio needs its bound: " << message;
}

TEST(Experiment, ReportQuantitiesComeFromTheRegistry) {
  ExperimentFolder folder("experiment_quantities");
  std::string good = std::string(kExperiment) + R"(metrics: [relmse, rmse]
tradeoffs: [[frame_ms, relmse], [memory_bytes, relmse], [prepare_seconds, relmse]]
budgets_ms: [16.7, 100]
error_targets: [0.1, 0.01]
claims:
  - {text: few photons are fast, kind: better, metric: frame_ms, run: photons=1000, than: photons=2000}
)";
  Experiment experiment = load_experiment(folder.write("good.yaml", good));
  ASSERT_EQ(experiment.report.tradeoffs.size(), 3u);
  EXPECT_EQ(experiment.report.tradeoffs[1], (std::pair<std::string, std::string>{"memory_bytes", "relmse"}));
  EXPECT_EQ(experiment.to_json()["budgets_ms"], json({16.7, 100}));
  EXPECT_EQ(load_experiment(folder.write("plain.yaml", kExperiment)).report.tradeoffs.front().first, "frame_ms");
  std::string message = error_of(folder, replace(good, "metric: frame_ms", "metric: frame_msec"));
  EXPECT_NE(message.find("did you mean 'frame_ms'"), std::string::npos) << message;
  message = error_of(folder, replace(good, "[memory_bytes, relmse]", "[memory_byte, relmse]"));
  EXPECT_NE(message.find("did you mean 'memory_bytes'"), std::string::npos) << message;
  EXPECT_NE(message.find("bad.yaml:12"), std::string::npos) << "names the line: " << message;
  message = error_of(folder, replace(good, "[memory_bytes, relmse]", "[memory_bytes, flip]"));
  EXPECT_NE(message.find("a metric the experiment measures"), std::string::npos) << message;
  message = error_of(folder, replace(good, "[memory_bytes, relmse]", "[receiver_pixels, relmse]"));
  EXPECT_NE(message.find("better one way"), std::string::npos) << message;
  message = error_of(folder, replace(good, "budgets_ms: [16.7, 100]", "budgets_ms: [100, 16.7]"));
  EXPECT_NE(message.find("increasing order"), std::string::npos) << message;
}

TEST(Experiment, FilterSelectsByKnobMethodAndLabel) {
  ExperimentFolder folder("experiment_filter");
  Experiment experiment = load_experiment(folder.write("a.yaml", kExperiment));
  auto count = [&](const std::string& filter) {
    size_t n = 0;
    for (const RunSpec& run : experiment.runs) n += run_matches_filter(experiment, run, filter) ? 1 : 0;
    return n;
  };
  EXPECT_EQ(count("k=20"), 2u);
  EXPECT_EQ(count("k=20,photons=1e3"), 1u);
  EXPECT_EQ(count("method=photon_map"), 6u);
  EXPECT_EQ(count("method=reference"), 0u);
  EXPECT_EQ(count("photons=2000"), 3u);
  EXPECT_EQ(count("nosuchknob=1"), 0u);
}
