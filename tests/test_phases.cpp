// Knob phases, knobs that apply, what runs share (prepare, update), the build cache and the keys of the
// shipped experiments. A synthetic method registered for these tests counts its prepare and update
// calls, so that sharing is asserted directly rather than inferred from timings.
#include <sys/wait.h>
#include <unistd.h>

#include <atomic>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>

#include <gtest/gtest.h>

#include "core/staging_folder.h"
#include "experiments/experiment.h"
#include "experiments/runner.h"
#include "store/build_cache.h"
#include "tests/test_support.h"

using namespace causticbench;
namespace fs = std::filesystem;

namespace {

std::atomic<int> prepare_calls{0}, update_calls{0}, render_calls{0};
std::vector<int> updated_frames;  // the frame index of every update() call, in order

// E_c = gain x (1 or 2 by blend) x (1 + sh_order) on every receiver: a known answer per knob set.
class SyntheticMethod : public CausticMethod {
 public:
  static const MethodInfo& static_info() {
    static const MethodInfo info = [] {
      MethodInfo m;
      m.name = "synthetic_phases";
      m.paper = "none (a test fixture)";
      m.summary = "counts its phases";
      m.params = {
          ParamSpec::choice("storage", "grid", {"grid", "sh"}, "build choice", ParamPhase::build),
          ParamSpec::integer("sh_order", 2, 1, 9, "applies only under storage: sh", ParamPhase::build)
              .only_when("storage", {"sh"}),
          ParamSpec::choice("blend", "nearest", {"nearest", "barycentric"}, "frame choice", ParamPhase::frame),
          ParamSpec::real("gain", 1.0, 0.0, 100.0, "render scale", ParamPhase::render),
      };
      m.capabilities.reflection = true;
      return m;
    }();
    return info;
  }
  const MethodInfo& info() const override { return static_info(); }
  void prepare(const PrepareContext& context, const ParamSet& build) override {
    ++prepare_calls;
    base_ = 1.0f + (build.text("storage") == "sh" ? static_cast<float>(build.integer("sh_order")) : 0.0f);
  }
  void update(const FrameContext& frame, const ParamSet& knobs) override {
    ++update_calls;
    updated_frames.push_back(static_cast<int>(frame.frame.frame));
    blend_ = knobs.text("blend") == "barycentric" ? 2.0f : 1.0f;
  }
  Image render(const GBuffer& gbuffer, const ParamSet& render) override {
    ++render_calls;
    return Image(gbuffer.width, gbuffer.height, 3, base_ * blend_ * static_cast<float>(render.real("gain")));
  }
  size_t memory_bytes() const override { return 0; }
  Counters counters() const override { return {}; }

 private:
  float base_ = 0.0f, blend_ = 0.0f;
};

// A temporary folder with the small glass sphere at 16 x 16 as scene.yaml.
class Folder : public causticbench::testing::TemporaryFolder {
 public:
  explicit Folder(const std::string& name) : TemporaryFolder("phases_" + name) {
    write("scene.yaml", causticbench::testing::replace_once(causticbench::testing::kSmallGlassSphere,
                                                            "resolution: [40, 40]", "resolution: [16, 16]"));
  }
};

const char* kHeader = R"(scene: scene.yaml
reference: {photons_per_pass: 20000, max_passes: 1, target_error: 0}
repetitions: 2
metrics: [relmse, energy_ratio]
)";

nlohmann::json read_json(const std::string& path) {
  std::ifstream stream(path);
  return nlohmann::json::parse(stream);
}

std::vector<nlohmann::json> records(const std::string& runs) {
  std::vector<nlohmann::json> result;
  for (const auto& entry : fs::directory_iterator(runs)) {
    if (entry.path().filename().string().rfind(".partial-", 0) == 0) continue;
    result.push_back(read_json((entry.path() / "record.json").string()));
  }
  return result;
}

}  // namespace

TEST(KnobsThatApply, ResolveDropsThemAndRejectsThemWhenSet) {
  const std::vector<ParamSpec>& specs = SyntheticMethod::static_info().params;
  ParamSet defaults = ParamDict{}.resolve(specs, "synthetic");
  EXPECT_FALSE(defaults.has("sh_order")) << "a knob that does not apply is absent";
  ParamDict sh;
  sh.set_assignment("storage=sh", "test");
  EXPECT_EQ(sh.resolve(specs, "synthetic").integer("sh_order"), 2) << "it applies: its default";
  ParamDict wrong;
  wrong.set_assignment("sh_order=4", "--set");
  std::string message = causticbench::testing::input_error_message([&] { wrong.resolve(specs, "synthetic"); });
  EXPECT_NE(message.find("sh_order"), std::string::npos) << message;
  EXPECT_NE(message.find("storage is sh"), std::string::npos) << message;
  EXPECT_NE(message.find("storage is grid"), std::string::npos) << message;
  EXPECT_FALSE(wrong.resolve(specs, "synthetic", {"sh_order"}).has("sh_order")) << "droppable where swept";
}

TEST(KnobsThatApply, SweepsCollapseAndFixedKnobsThatNeverApplyAreErrors) {
  ScopedMethodRegistration registration({&SyntheticMethod::static_info, [] { return std::make_unique<SyntheticMethod>(); }});
  Folder folder("collapse");
  // 2 storages x 3 orders: grid x 3 orders collapse into one run; sh keeps 3.
  Experiment experiment = load_experiment(folder.write("sweep.yaml", std::string(kHeader) + R"(methods:
  - method: synthetic_phases
    sweep: {storage: [grid, sh], sh_order: [1, 2, 3]}
)"));
  ASSERT_EQ(experiment.runs.size(), 4u);
  std::set<std::string> labels;
  for (const RunSpec& run : experiment.runs) labels.insert(run.label);
  EXPECT_TRUE(labels.count("synthetic_phases storage=grid")) << "no sh_order in the grid run's label";
  EXPECT_TRUE(labels.count("synthetic_phases sh_order=3 storage=sh"));
  std::string fixed = causticbench::testing::input_error_message([&] {
    load_experiment(folder.write("fixed.yaml", std::string(kHeader) + R"(methods:
  - method: synthetic_phases
    build: {sh_order: 3}
)"));
  });
  EXPECT_NE(fixed.find("fixed.yaml:7"), std::string::npos) << fixed;
  EXPECT_NE(fixed.find("storage is grid"), std::string::npos) << fixed;
  std::string never = causticbench::testing::input_error_message([&] {
    load_experiment(folder.write("never.yaml", std::string(kHeader) + R"(methods:
  - method: synthetic_phases
    sweep: {sh_order: [1, 2]}
)"));
  });
  EXPECT_NE(never.find("applies to none"), std::string::npos) << never;
  std::string phase = causticbench::testing::input_error_message([&] {
    load_experiment(folder.write("phase.yaml", std::string(kHeader) + R"(methods:
  - method: synthetic_phases
    build: {blend: barycentric}
)"));
  });
  EXPECT_NE(phase.find("'blend' is a frame knob"), std::string::npos) << phase;
}

// Runs that differ only in frame or render knobs share one prepare(); those that differ only in
// render knobs also share update(); each still gets its own answer.
TEST(Phases, RunsShareWhatTheirKnobsAllow) {
  ScopedMethodRegistration registration({&SyntheticMethod::static_info, [] { return std::make_unique<SyntheticMethod>(); }});
  Folder folder("share");
  Experiment experiment = load_experiment(folder.write("share.yaml", std::string(kHeader) + R"(methods:
  - method: synthetic_phases
    sweep: {blend: [nearest, barycentric], gain: [1, 2, 3]}
)"));
  ASSERT_EQ(experiment.runs.size(), 6u);
  prepare_calls = update_calls = render_calls = 0;
  RunOptions options;
  options.results = folder.path("results");
  options.threads = 1;
  RunSummary summary = run_experiment(experiment, options);
  EXPECT_EQ(summary.completed, 6u);
  EXPECT_EQ(prepare_calls.load(), 1) << "one build for all six runs";
  // Per frame knob set: one warm-up pass and 2 timed passes over 1 frame, one update() each.
  EXPECT_EQ(update_calls.load(), 2 * 3);
  EXPECT_EQ(render_calls.load(), 6 * 3);
  for (const nlohmann::json& record : records(options.results + "/" + experiment.name + "/runs")) {
    ASSERT_EQ(record["status"], "ok") << record.dump(2);
    EXPECT_EQ(record["frames"][0]["update_ms"].size(), 2u);
    EXPECT_EQ(record["prepare"]["source"], "computed");
    EXPECT_EQ(record["prepare"]["build_key"], "") << "this method declares no build dependencies";
    EXPECT_TRUE(record["frame"].contains("blend"));
    EXPECT_FALSE(record["build"].contains("sh_order"));
  }
}

// The timing protocol plays the sequence as an animation: a warm-up pass, then every timed pass runs
// the frames in order, so update() sees a new frame (a new light direction) every time it is timed.
TEST(Phases, UpdatesFollowTheAnimationOnEveryPass) {
  ScopedMethodRegistration registration({&SyntheticMethod::static_info, [] { return std::make_unique<SyntheticMethod>(); }});
  Folder folder("animation");
  folder.write("scene.yaml", "frames: 3\n" + causticbench::testing::replace_once(causticbench::testing::kSmallGlassSphere,
                                                                                   "resolution: [40, 40]", "resolution: [8, 8]"));
  Experiment experiment = load_experiment(folder.write("animation.yaml", std::string(kHeader) + R"(frames: all
methods:
  - method: synthetic_phases
)"));
  updated_frames.clear();
  RunOptions options;
  options.results = folder.path("results");
  run_experiment(experiment, options);
  EXPECT_EQ(updated_frames, (std::vector<int>{0, 1, 2, 0, 1, 2, 0, 1, 2})) << "warm-up and 2 timed passes, in order";
  nlohmann::json record = records(options.results + "/" + experiment.name + "/runs").front();
  ASSERT_EQ(record["frames"].size(), 3u);
  for (const nlohmann::json& frame : record["frames"]) EXPECT_EQ(frame["update_ms"].size(), 2u) << "per frame, per pass";
}

// photon_map on a static scene stores its photons: the second variant, a second experiment and a
// second process load them; the loaded runs measure the same as the computed ones.
TEST(BuildCache, ReusedAcrossVariantsExperimentsAndProcesses) {
  Folder folder("cache");
  std::string body = std::string(kHeader) + R"(variants: [{resolution: [16, 16]}, {name: other_camera, camera: {position: [1, 2.5, 1.5]}}]
methods:
  - method: photon_map
    build: {photons: 20000}
    sweep: {k: [10, 20]}
)";
  RunOptions options;
  options.results = folder.path("results");
  options.threads = 1;
  Experiment first = load_experiment(folder.write("first.yaml", "name: first\n" + body));
  run_experiment(first, options);
  std::map<std::string, std::string> source_by_variant;
  std::map<std::string, double> relmse_by_label;
  std::set<std::string> keys;
  for (const nlohmann::json& record : records(options.results + "/first/runs")) {
    ASSERT_EQ(record["status"], "ok") << record.dump(2);
    source_by_variant[record["variant"]] = record["prepare"]["source"];
    keys.insert(record["prepare"]["build_key"].get<std::string>());
    EXPECT_GT(record["prepare_seconds"].get<double>(), 0.0);
  }
  EXPECT_EQ(keys.size(), 1u) << "one build for both cameras";
  EXPECT_EQ(source_by_variant["16x16"], "computed");
  EXPECT_EQ(source_by_variant["other_camera"], "loaded");
  std::string key = *keys.begin();
  ASSERT_TRUE(fs::is_regular_file(options.results + "/builds/" + key + "/build.json"));
  EXPECT_EQ(read_json(options.results + "/builds/" + key + "/build.json")["method"], "photon_map");

  Experiment second = load_experiment(folder.write("second.yaml", "name: second\n" + body));
  run_experiment(second, options);
  for (const nlohmann::json& record : records(options.results + "/second/runs")) {
    EXPECT_EQ(record["prepare"]["source"], "loaded") << record["label"];
    EXPECT_EQ(record["prepare"]["build_key"], key);
  }
  for (const nlohmann::json& record : records(options.results + "/first/runs")) relmse_by_label[record["label"]] = record["metrics"]["relmse"];
  for (const nlohmann::json& record : records(options.results + "/second/runs")) {
    EXPECT_EQ(record["metrics"]["relmse"].get<double>(), relmse_by_label.at(record["label"])) << record["label"];
  }

  // Another process, through `render --build-cache`: loaded.
  std::string output;
  int code = causticbench::testing::run_command(std::string(CAUSTICBENCH_BINARY) + " -q render " + folder.path("scene.yaml") +
                                      " --method photon_map --set photons=20000 --resolution 16x16 --out " +
                                      folder.path("render") + " --build-cache " + options.results + "/builds",
                                  output);
  ASSERT_EQ(code, 0) << output;
  nlohmann::json rendered = read_json(folder.path("render/record.json"));
  EXPECT_EQ(rendered["prepare"]["source"], "loaded");
  EXPECT_EQ(rendered["prepare"]["build_key"], key);
}

// A build with no caustic photon at all (the dish turned over sends every photon to the sky) is stored
// and loaded like any other, and renders zeros.
TEST(BuildCache, AnEmptyBuildIsStoredAndLoaded) {
  Folder folder("empty_build");
  for (const char* expected : {"computed", "loaded"}) {
    std::string output;
    int code = causticbench::testing::run_command(
        std::string(CAUSTICBENCH_BINARY) + " -q render " + CAUSTICBENCH_SCENES + "/paraboloid_turned_over.yaml" +
            " --method photon_map --set photons=20000 --resolution 8x8 --out " + folder.path(expected) +
            " --build-cache " + folder.path("builds"),
        output);
    ASSERT_EQ(code, 0) << output;
    nlohmann::json record = read_json(folder.path(std::string(expected) + "/record.json"));
    EXPECT_EQ(record["prepare"]["source"], expected);
    EXPECT_EQ(record["caustic_flux_on_receivers"], 0.0);
  }
}

// Two processes that need the same missing build at once: both succeed and exactly one complete build
// is left, with no staging folder.
TEST(BuildCache, ConcurrentProcessesLeaveOneCompleteBuild) {
  Folder folder("concurrent");
  std::string cache = folder.path("builds");
  std::vector<pid_t> children;
  for (int i = 0; i < 2; ++i) {
    pid_t child = fork();
    if (child == 0) {
      std::string command = std::string(CAUSTICBENCH_BINARY) + " -q render " + folder.path("scene.yaml") +
                            " --method photon_map --set photons=200000 --resolution 8x8 --threads 1 --out " +
                            folder.path("out" + std::to_string(i)) + " --build-cache " + cache + " > /dev/null 2>&1";
      _exit(std::system(command.c_str()) == 0 ? 0 : 1);
    }
    children.push_back(child);
  }
  for (pid_t child : children) {
    int status = 0;
    waitpid(child, &status, 0);
    EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0);
  }
  std::vector<std::string> entries;
  for (const auto& entry : fs::directory_iterator(cache)) entries.push_back(entry.path().filename().string());
  ASSERT_EQ(entries.size(), 1u) << "one build, no staging folder left";
  EXPECT_TRUE(fs::is_regular_file(fs::path(cache) / entries[0] / "build.json"));
  EXPECT_TRUE(fs::is_regular_file(fs::path(cache) / entries[0] / "photons.bin"));
}

// The interleaving at the store: two stagings of one build folder; the first to commit wins, the
// other's content is discarded and its staging folder removed.
TEST(BuildCache, FirstRenameWinsTheSecondIsDiscarded) {
  Folder folder("interleave");
  std::string final_path = folder.path("builds/abc");
  fs::create_directories(folder.path("builds"));
  {
    StagingFolder first(final_path), second(final_path);
    ASSERT_NE(first.path(), second.path()) << "stagings of one process must not collide";
    std::ofstream(first.path() + "/content") << "first";
    std::ofstream(second.path() + "/content") << "second";
    EXPECT_TRUE(first.commit_if_absent());
    EXPECT_FALSE(second.commit_if_absent());
  }
  std::ifstream content(final_path + "/content");
  std::string text;
  content >> text;
  EXPECT_EQ(text, "first");
  size_t entries = 0;
  for ([[maybe_unused]] const auto& entry : fs::directory_iterator(folder.path("builds"))) ++entries;
  EXPECT_EQ(entries, 1u);
}

TEST(BuildCache, AStoredBuildIsUsedOnlyWhenItsRecordAndFilesCheckOut) {
  Folder folder("mismatch");
  std::string cache = folder.path("builds");
  nlohmann::json dependencies = {{"object", 1}};
  std::string key = build_cache_key("photon_map", dependencies);
  std::string build = cache + "/" + key;
  EXPECT_FALSE(find_stored_build(cache, key, "photon_map", dependencies)) << "nothing stored";
  fs::create_directories(build);
  std::ofstream(build + "/data.bin") << "twelve bytes";
  auto write_record = [&](const nlohmann::json& stored_dependencies) {
    std::ofstream(build + "/build.json") << nlohmann::json{{"method", "photon_map"},
                                                           {"version", kBuildCacheVersion},
                                                           {"dependencies", stored_dependencies},
                                                           {"files", build_file_checksums(build)},
                                                           {"prepare_seconds", 1.0}}
                                                .dump();
  };
  auto problem = [&] { return find_stored_build(cache, key, "photon_map", dependencies).value().problem; };
  write_record({{"object", 2}});
  EXPECT_NE(problem().find("other dependencies"), std::string::npos) << problem();
  std::ofstream(build + "/build.json") << "{truncated";
  EXPECT_NE(problem().find("unreadable"), std::string::npos) << problem();
  write_record(dependencies);
  EXPECT_EQ(problem(), "") << "complete and matching";
  std::ofstream(build + "/data.bin") << "twelve bytez";  // same size, other content
  EXPECT_NE(problem().find("checksum"), std::string::npos) << problem();
  std::ofstream(build + "/data.bin") << "short";
  EXPECT_NE(problem().find("checksum"), std::string::npos) << problem();
}

// Knob phases moved pinhole's per-frame knobs from build to frame, and knobs that apply left the key
// of knobs that always apply unchanged: every shipped experiment keeps the run keys it had before
// (tests/data/shipped_run_keys.txt, written by `causticbench run FILE --dry-run` before the change).
// A default changed on purpose changes the keys of the runs at that default, and only those: lpi's
// `orientation: auto` (issue 52) rewrote the keys of the 25 lpi runs at the default orientation (the
// quickstart's and the study's), nothing else.
TEST(Keys, ShippedExperimentsKeepTheirRunKeys) {
  std::ifstream golden(std::string(CAUSTICBENCH_SOURCE_DIR) + "/tests/data/shipped_run_keys.txt");
  ASSERT_TRUE(golden);
  std::map<std::string, std::set<std::string>> expected;
  std::string experiment, key;
  while (golden >> experiment >> key) expected[experiment].insert(key);
  ASSERT_GE(expected.size(), 8u);
  for (const auto& [name, keys] : expected) {
    Experiment loaded = load_experiment(std::string(CAUSTICBENCH_SOURCE_DIR) + "/configs/experiments/" + name + ".yaml");
    std::set<std::string> actual;
    for (const RunSpec& run : loaded.runs) actual.insert(run.key);
    EXPECT_EQ(actual, keys) << name;
  }
}
