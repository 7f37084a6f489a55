// The tiny experiment folder the experiment and runner tests share (test_experiments.cpp, test_runner.cpp).
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "experiments/experiment.h"
#include "tests/test_support.h"

namespace causticbench::experiment_testing {

using namespace causticbench;
namespace fs = std::filesystem;

// A temporary folder with a tiny scene and experiment files.
class ExperimentFolder : public causticbench::testing::TemporaryFolder {
 public:
  explicit ExperimentFolder(const std::string& name) : TemporaryFolder(name) {
    write("scene.yaml", causticbench::testing::replace_once(causticbench::testing::kSmallGlassSphere,
                                                            "resolution: [40, 40]", "resolution: [24, 24]"));
  }
};

inline const char* const kExperiment = R"(name: tiny
scene: scene.yaml
reference: {photons_per_pass: 100000, max_passes: 3, target_error: 0}
repetitions: 1
methods:
  - method: photon_map
    render: {max_radius: 0.3}
    sweep:
      photons: [1000, 2000]
      k: [10, 20, 30]
)";

inline std::string error_of(const ExperimentFolder& folder, const std::string& text) {
  return causticbench::testing::input_error_message([&] { load_experiment(folder.write("bad.yaml", text)); });
}

inline constexpr auto replace = causticbench::testing::replace_once;

inline std::vector<std::string> stored_runs(const std::string& runs_folder) {
  std::vector<std::string> keys;
  if (!fs::is_directory(runs_folder)) return keys;
  for (const auto& entry : fs::directory_iterator(runs_folder)) {
    std::string name = entry.path().filename().string();
    if (name.rfind(".partial-", 0) == 0) continue;
    keys.push_back(name);
  }
  return keys;
}

}  // namespace causticbench::experiment_testing
