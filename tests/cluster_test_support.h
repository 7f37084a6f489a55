// The small sweep of the cluster tests (test_cluster.cpp, test_slurm.cpp) and a folder holding it.
#pragma once

#include <fcntl.h>
#include <sys/stat.h>

#include <atomic>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <set>
#include <string>
#include <thread>
#include <vector>

#include "experiments/experiment.h"
#include "store/result_paths.h"
#include "store/run_folders.h"
#include "tests/reliability/store_harness.h"
#include "tests/test_support.h"

namespace causticbench::testing {

// Three groups sharing one prepare() each (photons is a build knob of photon_map), two runs per group.
inline const char* const kClusterSweep = R"(name: sweep
scene: scene.yaml
reference: {photons_per_pass: 20000, max_passes: 2, target_error: 0}
repetitions: 1
methods:
  - method: photon_map
    render: {max_radius: 0.3}
    sweep:
      photons: [1000, 2000, 3000]
      k: [10, 20]
)";

// A temporary folder with the small glass sphere at 24 x 24 pixels, an experiment file and a results folder.
class SweepFolder : public TemporaryFolder {
 public:
  explicit SweepFolder(const std::string& name, const std::string& experiment = kClusterSweep)
      : TemporaryFolder("cluster_" + name) {
    write("scene.yaml", replace_once(kSmallGlassSphere, "resolution: [40, 40]", "resolution: [24, 24]"));
    file = write("sweep.yaml", experiment);
    results = path("results");
  }
  Experiment experiment() const { return load_experiment(file); }
  // `causticbench run` of the experiment with `extra` options, into the results folder, without report.
  store_harness::Finished run(const std::vector<std::string>& extra) {
    std::vector<std::string> arguments = {"run", file, "--results", results, "--no-report"};
    arguments.insert(arguments.end(), extra.begin(), extra.end());
    return command(arguments);
  }
  store_harness::Finished command(const std::vector<std::string>& arguments) {
    return store_harness::run_process(arguments, path("output_" + std::to_string(outputs_++) + ".txt"));
  }
  std::string file, results;

 private:
  int outputs_ = 0;
};

// The keys of the runs stored (complete and passing their checks) in a runs folder.
inline std::set<std::string> stored_keys(const std::string& runs_folder) {
  std::set<std::string> keys;
  if (!std::filesystem::is_directory(runs_folder)) return keys;
  for (const auto& entry : std::filesystem::directory_iterator(runs_folder)) {
    if (run_is_stored(entry.path().string())) keys.insert(entry.path().filename().string());
  }
  return keys;
}

// A store lock held by a job "on another host": its file, with that host's holder line, refreshed every
// 100 ms as the job's heartbeat would until stop() (the job dies) or destruction.
class ForeignLock {
 public:
  ForeignLock(const std::string& path, const std::string& host) : path_(path) {
    std::filesystem::create_directories(std::filesystem::path(path).parent_path());
    std::ofstream(path) << "pid 77 on " << host << " started 5 token 02\n";
    heartbeat_ = std::thread([this] {
      while (beating_) {
        ::utimensat(AT_FDCWD, path_.c_str(), nullptr, 0);
        std::this_thread::sleep_for(std::chrono::milliseconds(100));
      }
    });
  }
  ~ForeignLock() { stop(); }
  ForeignLock(const ForeignLock&) = delete;
  ForeignLock& operator=(const ForeignLock&) = delete;
  void stop() {
    beating_ = false;
    if (heartbeat_.joinable()) heartbeat_.join();
  }

 private:
  std::string path_;
  std::atomic<bool> beating_{true};
  std::thread heartbeat_;
};

}  // namespace causticbench::testing
