#include "store/result_paths.h"

#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <filesystem>

#include <fmt/format.h>

#include "core/errors.h"
#include "core/files.h"

namespace causticbench {

void check_results_folder(const std::string& path) { check_writable_folder("--results", "results", path); }

void check_writable_folder(const std::string& option, const std::string& what, const std::string& path) {
  namespace fs = std::filesystem;
  auto refuse = [&](const std::string& found) {
    throw InputError(fmt::format("{}: expected a folder to write {} into, found {}", option, what, found));
  };
  if (path.empty()) refuse("an empty path");
  // The folder itself, or else its nearest existing ancestor, which must then be a writable folder.
  fs::path existing = fs::absolute(fs::path(path));
  while (true) {
    std::error_code error;
    fs::file_status status = fs::status(existing, error);
    if (error && error.value() != ENOENT) refuse(fmt::format("'{}': {}", existing.string(), os_error_text(error.value())));
    // A link to nothing: creating the folder would fail with "File exists".
    if (!fs::exists(status) && fs::is_symlink(fs::symlink_status(existing, error)))
      refuse(fmt::format("'{}', a symbolic link to '{}', which does not exist", existing.string(),
                         fs::read_symlink(existing, error).string()));
    if (fs::exists(status)) {
      // (A file above the folder is ENOTDIR above; a file here is the folder itself.)
      if (!fs::is_directory(status)) refuse(fmt::format("'{}', which is a file", path));
      if (::access(existing.c_str(), W_OK | X_OK) != 0) {
        refuse(fmt::format("'{}', where '{}' cannot be written: {}", path, existing.string(), os_error_text(errno)));
      }
      return;
    }
    if (!existing.has_parent_path() || existing.parent_path() == existing) return;
    existing = existing.parent_path();
  }
}

namespace fs = std::filesystem;

std::string experiment_folders_hint(const std::string& given) {
  std::vector<std::string> inside;
  std::error_code error;
  for (const auto& entry : fs::directory_iterator(given, error)) {
    if (entry.is_directory(error) && fs::is_regular_file(entry.path() / "experiment.json", error))
      inside.push_back((fs::path(given) / entry.path().filename()).string());
  }
  std::sort(inside.begin(), inside.end());
  return inside.empty() ? "; `causticbench run EXPERIMENT.yaml` writes one as results/<experiment>/"
                        : "; the experiment folders inside it are: " + join(inside, ", ");
}

std::string ResultPaths::experiment(const std::string& name) const { return (fs::path(results) / name).string(); }
std::string ResultPaths::run(const std::string& experiment_name, const std::string& key) const {
  return (fs::path(results) / experiment_name / "runs" / key).string();
}
std::string ResultPaths::reference(const std::string& key) const {
  return (fs::path(results) / "references" / key).string();
}
std::string ResultPaths::builds() const { return (fs::path(results) / "builds").string(); }
std::string ResultPaths::reference_lock(const std::string& key) const {
  return (fs::path(results) / ".locks" / "references" / (key + ".lock")).string();
}
std::string ResultPaths::run_lock(const std::string& experiment_name, const std::string& key) const {
  return (fs::path(results) / ".locks" / "runs" / experiment_name / (key + ".lock")).string();
}
std::string ResultPaths::frame_file(int frame, const std::string& prefix) {
  return fmt::format("{}_{:04d}", prefix, frame);
}

}  // namespace causticbench
