// The study's experiments (configs/experiments/study_*.yaml, issue 14): each validates, compares several
// methods on the trade-off axes the study needs, and its cheapest setting of every method runs end to
// end at a tiny resolution, after which `causticbench summarize` reads them all. The cheapest setting is
// each method's first run (the ladders are written cheapest first); the tiny copy differs from the file
// only in its one-line overrides, reference, repetitions and (an animated study) frames.
#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "experiments/experiment.h"
#include "tests/test_support.h"

namespace causticbench {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;


// The method ladders. Left out: the experiments that compare cases, not ladders, at one setting per
// method, whose variants name scene files of their own (which the tiny copy's one rewritten `scene:`
// line would not reach): those that show a case table (the extremes, case_table: true; run by
// tests/test_extremes.cpp) and those that declare a capability matrix (study_capabilities.yaml;
// tests/test_capability_matrix.cpp validates it and tests/test_capabilities.cpp runs its cases).
std::vector<fs::path> study_files() {
  std::vector<fs::path> files;
  for (const fs::path& file : testing::shipped_experiments("study_")) {
    const Experiment experiment = load_experiment(file.string());
    if (!experiment.report.case_table && experiment.report.capability_matrix.is_null()) files.push_back(file);
  }
  return files;
}


// The study at 24 x 24 with a two-pass reference, one repetition and at most three frames; the scene
// named by absolute path.
std::string tiny_copy(const std::string& text) {
  std::string tiny = std::regex_replace(text, std::regex("\nscene: \\.\\./scenes/"),
                                        "\nscene: " + std::string(CAUSTICBENCH_SCENES) + "/");
  tiny = testing::tiny_experiment(tiny, 24);
  // An animated study: its first three frames, enough for temporal flicker.
  return std::regex_replace(tiny, std::regex("\nframes: [^\n]*"), "\nframes: {first: 0, count: 3}");
}

TEST(Study, EveryStudyValidatesAndComparesMethodsOnTimeMemoryAndPrecomputation) {
  const std::vector<fs::path> files = study_files();
  ASSERT_GE(files.size(), 2u);
  for (const fs::path& file : files) {
    Experiment experiment = load_experiment(file.string());
    std::map<std::string, size_t> runs_per_method;
    for (const RunSpec& run : experiment.runs) ++runs_per_method[run.method];
    EXPECT_GE(runs_per_method.size(), 3u) << file;
    for (const auto& [method, runs] : runs_per_method) EXPECT_GE(runs, 2u) << file << ": " << method << " has no ladder";
    std::vector<std::string> axes;
    for (const auto& [x, y] : experiment.report.tradeoffs) {
      EXPECT_EQ(y, experiment.primary_metric) << file;
      axes.push_back(x);
    }
    EXPECT_EQ(axes, (std::vector<std::string>{"frame_ms", "memory_bytes", "prepare_seconds"})) << file;
    EXPECT_NE(experiment.primary_metric, "relmse") << file << ": see the studies' header comments";
  }
}

// The cheapest settings that stop by design with a clear error, (study file, method) -> a part of the
// error: a method that cannot model the study's scene and says so.
const std::map<std::pair<std::string, std::string>, std::string> kRefused = {
    {{"study_ring_forest", "csl"}, "light 'forest' is an environment light; csl renders directional and point lights only"},
};

TEST(Study, CheapestSettingOfEveryMethodRunsEndToEndAndIsSummarized) {
  testing::TemporaryFolder folder("study_end_to_end");
  const std::string results = folder.path("results");
  std::vector<std::string> experiment_folders;
  for (const fs::path& file : study_files()) {
    const std::string tiny = folder.write(file.filename().string(), tiny_copy(testing::read_whole_file(file)));
    Experiment experiment = load_experiment(tiny);
    std::map<std::string, const RunSpec*> cheapest;  // the first run of each method
    for (const RunSpec& run : experiment.runs) cheapest.emplace(run.method, &run);
    for (const auto& [method, run] : cheapest) {
      std::string filter = "method=" + method;
      for (const auto& [knob, value] : run->swept) filter += "," + knob + "=" + value;
      std::string output;
      int code = testing::run_command(std::string(CAUSTICBENCH_BINARY) + " -q run " + tiny + " --results " + results +
                                          " --no-report --filter '" + filter + "'",
                                      output);
      ASSERT_EQ(code, 0) << file << " " << filter << "\n" << output;
      EXPECT_NE(output.find("1 selected"), std::string::npos) << output;
      const fs::path record_path = fs::path(results) / experiment.name / "runs" / run->key / "record.json";
      ASSERT_TRUE(fs::is_regular_file(record_path)) << record_path;
      const json record = json::parse(testing::read_whole_file(record_path));
      // Every cheapest setting runs ok, but those kRefused lists, which stop with their clear error.
      const auto refused = kRefused.find({fs::path(file).stem().string(), method});
      if (refused == kRefused.end()) {
        EXPECT_EQ(record.at("status"), "ok") << record_path << ": " << record.value("error", "");
        if (record.at("status") != "ok") continue;
        EXPECT_TRUE(record.at("metrics").contains(experiment.primary_metric)) << record_path;
        EXPECT_EQ(record.at("metrics").value("nonfinite_pixels", 0.0), 0.0) << record_path;
      } else {
        EXPECT_EQ(record.at("status"), "failed") << record_path << ": listed as refused";
        EXPECT_NE(record.value("error", "").find(refused->second), std::string::npos) << record.value("error", "");
      }
    }
    experiment_folders.push_back(fs::path(results) / experiment.name);
  }
  std::string output, command = std::string(CAUSTICBENCH_BINARY) + " summarize";
  for (const std::string& experiment : experiment_folders) command += " " + experiment;
  ASSERT_EQ(testing::run_command(command + " --out " + folder.path("summary"), output), 0) << output;
  const json summary = json::parse(testing::read_whole_file(folder.path("summary") + "/summary.json"));
  EXPECT_EQ(summary.at("experiments").size(), experiment_folders.size());
  for (const json& scene : summary.at("scenes")) EXPECT_FALSE(scene.at("budgets").empty()) << scene.dump();
}

}  // namespace
}  // namespace causticbench
