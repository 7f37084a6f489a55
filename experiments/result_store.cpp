#include "experiments/result_store.h"

#include <filesystem>

#include <fmt/format.h>

namespace causticbench {

namespace fs = std::filesystem;

std::string ResultPaths::experiment(const std::string& name) const { return (fs::path(results) / name).string(); }
std::string ResultPaths::run(const std::string& experiment_name, const std::string& key) const {
  return (fs::path(results) / experiment_name / "runs" / key).string();
}
std::string ResultPaths::reference(const std::string& key) const {
  return (fs::path(results) / "references" / key).string();
}
std::string ResultPaths::builds() const { return (fs::path(results) / "builds").string(); }
std::string ResultPaths::frame_file(int frame, const std::string& prefix) {
  return fmt::format("{}_{:04d}", prefix, frame);
}

bool run_is_stored(const std::string& run_folder) { return fs::is_regular_file(fs::path(run_folder) / "record.json"); }

}  // namespace causticbench
