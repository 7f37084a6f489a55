// The runner: shards that partition an experiment's runs, resume after SIGKILL with nothing lost or
// duplicated, and a tiny experiment run end to end with its report.
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
using namespace causticbench::experiment_testing;
using causticbench::testing::run_command;
using nlohmann::json;

TEST(Runner, ShardsPartitionTheRuns) {
  ExperimentFolder folder("experiment_shards");
  Experiment experiment = load_experiment(folder.write("a.yaml", kExperiment));
  size_t total = 0;
  for (int shard = 0; shard < 4; ++shard) {
    RunOptions options;
    options.dry_run = true;
    options.shard_index = shard;
    options.shard_count = 4;
    options.results = folder.path("results");
    total += run_experiment(experiment, options).selected;
  }
  EXPECT_EQ(total, experiment.runs.size());
  int index, count;
  EXPECT_THROW(parse_shard("4/4", index, count), InputError);
  EXPECT_THROW(parse_shard("a/b", index, count), InputError);
  parse_shard("1/3", index, count);
  EXPECT_EQ(index, 1);
  EXPECT_EQ(count, 3);
}

// A runner killed with SIGKILL in the middle of a sweep leaves only complete runs; the next
// invocation completes the sweep with exactly one record per run.
TEST(Runner, ResumesAfterSigkillWithNothingLostOrDuplicated) {
  ExperimentFolder folder("experiment_resume");
  // Heavy enough runs (200k photons, 4 updates each) that the kill lands mid-sweep.
  std::string experiment_file = folder.write("resume.yaml", replace(replace(kExperiment, "[1000, 2000]", "[200000, 210000]"),
                                                                    "repetitions: 1", "repetitions: 3"));
  std::string results = folder.path("results");
  std::string runs = results + "/tiny/runs";
  pid_t child = fork();
  ASSERT_GE(child, 0);
  if (child == 0) {
    int devnull = open("/dev/null", O_WRONLY);
    dup2(devnull, 1);
    dup2(devnull, 2);
    execl(CAUSTICBENCH_BINARY, CAUSTICBENCH_BINARY, "run", experiment_file.c_str(), "--results", results.c_str(),
          "--no-report", "--threads", "1", static_cast<char*>(nullptr));
    _exit(127);
  }
  auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(120);
  while (stored_runs(runs).empty() && std::chrono::steady_clock::now() < deadline) {
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  kill(child, SIGKILL);
  int status = 0;
  waitpid(child, &status, 0);
  ASSERT_TRUE(WIFSIGNALED(status)) << "the runner finished before it could be killed";
  std::vector<std::string> after_kill = stored_runs(runs);
  ASSERT_GE(after_kill.size(), 1u);
  ASSERT_LT(after_kill.size(), 6u) << "the kill did not land mid-sweep";
  for (const std::string& key : after_kill) {
    EXPECT_TRUE(fs::is_regular_file(runs + "/" + key + "/record.json")) << key << " is half written";
    EXPECT_TRUE(fs::is_regular_file(runs + "/" + key + "/frame_0000.exr")) << key << " is half written";
  }
  std::string output;
  int code = run_command(std::string(CAUSTICBENCH_BINARY) + " run " + experiment_file + " --results " + results + " --no-report",
                         output);
  ASSERT_EQ(code, 0) << output;
  EXPECT_NE(output.find(std::to_string(after_kill.size()) + " already stored"), std::string::npos) << output;
  std::vector<std::string> complete = stored_runs(runs);
  EXPECT_EQ(complete.size(), 6u);
  Experiment experiment = load_experiment(experiment_file);
  std::set<std::string> expected;
  for (const RunSpec& run : experiment.runs) expected.insert(run.key);
  EXPECT_EQ(std::set<std::string>(complete.begin(), complete.end()), expected);
  // No staging folder of the killed runner is left behind.
  for (const auto& entry : fs::directory_iterator(runs)) {
    EXPECT_NE(entry.path().filename().string().rfind(".partial-", 0), 0u) << entry.path();
  }
  // A third invocation has nothing to do.
  code = run_command(std::string(CAUSTICBENCH_BINARY) + " run " + experiment_file + " --results " + results + " --no-report",
                     output);
  EXPECT_NE(output.find("6 already stored, 0 run now"), std::string::npos) << output;
}

// The whole pipeline on a tiny experiment: reference, photon_map runs, metrics, report.
TEST(EndToEnd, TinyExperimentRunsAndReports) {
  ExperimentFolder folder("experiment_end_to_end");
  std::string experiment_file = folder.write("tiny.yaml", std::string(kExperiment) + R"(paper:
  title: made-up published numbers
  columns: [relmse]
  rows:
    - {method: photon_map, match: {photons: 2000, k: 20}, values: {relmse: 0.5}, note: invented for the test}
)");
  std::string results = folder.path("results");
  std::string output;
  int code = run_command(std::string(CAUSTICBENCH_BINARY) + " run " + experiment_file + " --results " + results, output);
  ASSERT_EQ(code, 0) << output;
  EXPECT_NE(output.find("6 run now, 0 failed"), std::string::npos) << output;
  std::string folder_path = results + "/tiny";
  for (const char* file : {"report.html", "report.md", "results.csv", "results.json", "experiment.json", "environment.json"}) {
    EXPECT_TRUE(fs::is_regular_file(folder_path + "/" + file)) << file;
  }
  std::ifstream markdown_stream(folder_path + "/report.md");
  std::string markdown((std::istreambuf_iterator<char>(markdown_stream)), std::istreambuf_iterator<char>());
  EXPECT_NE(markdown.find("photon_map k=20 photons=2000"), std::string::npos) << markdown.substr(0, 2000);
  // The paper's value stands beside our matching run.
  EXPECT_NE(markdown.find("| photon_map | k=20, photons=2000 | photon_map (k=20, max_radius=0.3, photons=2000) | 0.5 |"),
            std::string::npos)
      << markdown;
  EXPECT_NE(markdown.find("invented for the test"), std::string::npos);
  std::ifstream csv_stream(folder_path + "/results.csv");
  size_t lines = 0;
  for (std::string line; std::getline(csv_stream, line);) lines += line.empty() ? 0 : 1;
  EXPECT_EQ(lines, 7u);  // header + 6 runs
  // Every stored run measured a finite error against the reference.
  for (const auto& entry : fs::directory_iterator(folder_path + "/runs")) {
    std::ifstream record_stream(entry.path() / "record.json");
    nlohmann::json record = nlohmann::json::parse(record_stream);
    EXPECT_EQ(record["status"], "ok") << record["error"];
    double relmse = record["metrics"]["relmse"].get<double>();
    EXPECT_TRUE(std::isfinite(relmse) && relmse > 0.0) << relmse;
    EXPECT_EQ(record["frames"][0]["render_ms"].size(), 1u);
  }
  // Scene variants: each resolution gets its own reference, and every run records its variant, its
  // reference and how many receiver pixels it shaded (which grows with the resolution).
  std::string varied = folder.write("varied.yaml", replace(replace(std::string(kExperiment), "name: tiny", "name: varied"),
                                                           "      k: [10, 20, 30]", "      k: [10]") +
                                                       "variants: [{resolution: [12, 12]}, {resolution: [24, 24]}]\n");
  code = run_command(std::string(CAUSTICBENCH_BINARY) + " run " + varied + " --results " + results, output);
  ASSERT_EQ(code, 0) << output;
  EXPECT_NE(output.find("4 run now, 0 failed"), std::string::npos) << output;
  std::map<std::string, std::set<size_t>> receivers_by_variant;
  std::set<std::string> reference_keys;
  for (const auto& entry : fs::directory_iterator(results + "/varied/runs")) {
    std::ifstream record_stream(entry.path() / "record.json");
    nlohmann::json record = nlohmann::json::parse(record_stream);
    ASSERT_EQ(record["status"], "ok") << record["error"];
    receivers_by_variant[record["variant"].get<std::string>()].insert(record["receiver_pixels"].get<size_t>());
    reference_keys.insert(record["reference_key"].get<std::string>());
    EXPECT_TRUE(fs::is_regular_file(results + "/references/" + record["reference_key"].get<std::string>() + "/frame_0000.exr"));
  }
  ASSERT_EQ(receivers_by_variant.size(), 2u);
  ASSERT_EQ(receivers_by_variant["12x12"].size(), 1u);
  ASSERT_EQ(receivers_by_variant["24x24"].size(), 1u);
  size_t small = *receivers_by_variant["12x12"].begin(), large = *receivers_by_variant["24x24"].begin();
  EXPECT_GT(small, 0u);
  EXPECT_NEAR(static_cast<double>(large) / small, 4.0, 0.5);  // receiver pixels scale with the pixel count
  EXPECT_EQ(reference_keys.size(), 2u);

  // The reference cache is reused by a second experiment with the same scene and reference knobs.
  std::string second = folder.write("second.yaml", replace(std::string(kExperiment), "name: tiny", "name: second"));
  code = run_command(std::string(CAUSTICBENCH_BINARY) + " run " + second + " --results " + results + " --no-report", output);
  ASSERT_EQ(code, 0) << output;
  EXPECT_EQ(output.find("computing"), std::string::npos) << "the reference was computed again: " << output;
}
