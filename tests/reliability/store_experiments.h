// The experiments and checks that tests/test_reliability_store.cpp and tests/test_reliability_references.cpp
// drive the results store with: a one-run and a four-run photon_map experiment on a 16 x 16 glass sphere in
// a temporary folder (StoreFolder), whether a results folder holds every run complete (expect_complete),
// and the "N run now" count of a run's summary line. Processes and the reader's view: store_harness.h.
#pragma once

#include <gtest/gtest.h>

#include <filesystem>
#include <optional>
#include <regex>
#include <string>
#include <vector>

#include "experiments/experiment.h"
#include "experiments/reference_frames.h"
#include "tests/reliability/store_harness.h"
#include "tests/test_support.h"

namespace causticbench::store_harness {

// One photon_map run of a 16 x 16 glass sphere against a two-pass reference: every kind of write step
// of the store (reference, environment, build cache, run) in about 20 steps.
inline const char* const kOneRun = R"(name: store
scene: scene.yaml
reference: {photons_per_pass: 20000, max_passes: 2, target_error: 0, max_seconds: 0}
repetitions: 1
methods:
  - method: photon_map
    build: {photons: 1000}
    render: {k: 10, max_radius: 0.3}
)";

// Four runs in two build groups.
inline const char* const kFourRuns = R"(name: store
scene: scene.yaml
reference: {photons_per_pass: 20000, max_passes: 2, target_error: 0, max_seconds: 0}
repetitions: 1
methods:
  - method: photon_map
    render: {max_radius: 0.3}
    sweep:
      photons: [1000, 2000]
      k: [10, 20]
)";

// A reference that stops on its time cap after its first pass: two computations of it differ.
inline const std::string kTimeCapped = "reference: {photons_per_pass: 20000, max_passes: 100000, target_error: 0, max_seconds: 0.000001}";

class StoreFolder : public causticbench::testing::TemporaryFolder {
 public:
  explicit StoreFolder(const std::string& name, const std::string& experiment = kOneRun)
      : TemporaryFolder("store_" + name) {
    write("scene.yaml", causticbench::testing::replace_once(causticbench::testing::kSmallGlassSphere,
                                                            "resolution: [40, 40]", "resolution: [16, 16]"));
    experiment_file = write("store.yaml", experiment);
    results = path("results");
  }
  Experiment experiment() const { return load_experiment(experiment_file); }
  std::vector<std::string> run_arguments(const std::string& results_folder = "") const {
    return {"run", experiment_file, "--results", results_folder.empty() ? results : results_folder, "--no-report"};
  }
  Finished run(const std::vector<std::string>& extra = {}, const std::vector<std::string>& environment = {},
               const std::string& results_folder = "") const {
    std::vector<std::string> arguments = run_arguments(results_folder);
    arguments.insert(arguments.end(), extra.begin(), extra.end());
    return run_process(arguments, path("output_" + std::to_string(outputs_++) + ".txt"), environment);
  }

  std::string experiment_file, results;

 private:
  mutable int outputs_ = 0;
};

// Every run of the experiment is stored under `results`, passes the store's checks and was measured
// against the reference that is stored; nothing is half written and nothing left over.
inline void expect_complete(const Experiment& experiment, const std::string& results) {
  ResultPaths paths{results};
  std::optional<nlohmann::json> reference =
      stored_reference_checksums(paths, experiment.variants[0].reference_key, experiment.frames);
  ASSERT_TRUE(reference) << "the reference is stored";
  for (const RunSpec& run : experiment.runs) {
    StoredRun stored = inspect_stored_run(paths.run(experiment.name, run.key));
    ASSERT_EQ(stored.state, StoredRun::State::stored) << run.label << ": " << stored.problem;
    EXPECT_EQ(stored.record["status"], "ok") << stored.record["error"];
    EXPECT_EQ(stored.record["reference_images"], *reference) << run.label << " was measured against another reference";
  }
  EXPECT_EQ(half_written(results), std::vector<std::string>());
  EXPECT_EQ(leftovers(results), std::vector<std::string>());
}

inline std::string record_text(const Experiment& experiment, const std::string& results, const RunSpec& run) {
  return read_all(fs::path(ResultPaths{results}.run(experiment.name, run.key)) / "record.json");
}

// "N run now" of the summary line.
inline int runs_now(const std::string& output) {
  std::smatch match;
  return std::regex_search(output, match, std::regex("([0-9]+) run now")) ? std::stoi(match[1].str()) : -1;
}

}  // namespace causticbench::store_harness
