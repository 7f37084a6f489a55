#include "experiments/result_store.h"

#include <unistd.h>

#include <cerrno>
#include <filesystem>

#include <fmt/format.h>

#include "core/errors.h"
#include "core/files.h"
#include "core/hash.h"
#include "experiments/record_check.h"
#include "experiments/store_files.h"

namespace causticbench {

void check_results_folder(const std::string& path) { check_writable_folder("--results", "results", path); }

void check_writable_folder(const std::string& option, const std::string& what, const std::string& path) {
  namespace fs = std::filesystem;
  auto refuse = [&](const std::string& found) {
    throw InputError(fmt::format("{}: expected a folder to write {} into, found {}", option, what, found));
  };
  // The folder itself, or else its nearest existing ancestor, which must then be a writable folder.
  fs::path existing = fs::absolute(fs::path(path));
  while (true) {
    std::error_code error;
    fs::file_status status = fs::status(existing, error);
    if (error && error.value() != ENOENT) refuse(fmt::format("'{}': {}", existing.string(), os_error_text(error.value())));
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

bool measured_against_other_reference(const nlohmann::json& record, const std::string& current_reference_key) {
  const auto found = record.find("reference_key");
  if (found == record.end() || !found->is_string() || found->get<std::string>().empty()) return false;
  return !current_reference_key.empty() && found->get<std::string>() != current_reference_key;
}

StoredRun inspect_stored_run(const std::string& run_folder) {
  StoredRun stored;
  const std::string path = (fs::path(run_folder) / "record.json").string();
  std::error_code error;
  if (!fs::exists(run_folder, error)) return stored;
  stored.state = StoredRun::State::damaged;
  std::optional<std::string> text = read_file_bytes(path);
  if (!text) {
    stored.problem = fmt::format("{}: missing or unreadable", path);
    return stored;
  }
  nlohmann::json record = nlohmann::json::parse(*text, nullptr, /*allow_exceptions=*/false);
  std::string problem = record.is_discarded() ? "not valid JSON (truncated?)" : run_record_problem(record, run_folder);
  if (!problem.empty()) {
    stored.problem = fmt::format("{}: {}", path, problem);
    return stored;
  }
  stored.state = StoredRun::State::stored;
  stored.record = std::move(record);
  stored.record_hash = hash_text(*text);
  return stored;
}

bool run_is_stored(const std::string& run_folder) {
  return inspect_stored_run(run_folder).state == StoredRun::State::stored;
}

void store_run_folder(const std::string& run_folder, const std::vector<std::pair<std::string, std::string>>& images,
                      nlohmann::json record) {
  StagingFolder staging(run_folder);
  nlohmann::json checksums = nlohmann::json::object();
  for (const auto& [name, bytes] : images) {
    write_file_atomically((fs::path(staging.path()) / name).string(), bytes);
    checksums[name] = content_checksum(bytes);
  }
  record["images"] = checksums;
  // The record last: a folder is a run only with it, and it names what the images must be.
  write_text_atomically((fs::path(staging.path()) / "record.json").string(), record.dump(2) + "\n");
  staging.commit();
}

}  // namespace causticbench
