#include "store/build_cache.h"

#include <filesystem>
#include <fstream>

#include "core/files.h"
#include "core/hash.h"
#include "core/staging_folder.h"

namespace causticbench {

namespace fs = std::filesystem;

std::string build_cache_key(const std::string& method, const nlohmann::json& dependencies) {
  return hash_json({{"method", method}, {"version", kBuildCacheVersion}, {"dependencies", dependencies}});
}

nlohmann::json build_file_checksums(const std::string& folder) {
  nlohmann::json files = nlohmann::json::object();
  for (const auto& entry : fs::directory_iterator(folder)) {
    std::string name = entry.path().filename().string();
    if (name == "build.json" || !entry.is_regular_file()) continue;
    uint64_t bytes = 0;
    std::string hash = hash_file(entry.path().string(), bytes);
    files[name] = {{"bytes", bytes}, {"xxhash", hash}};
  }
  return files;
}

std::optional<StoredBuild> find_stored_build(const std::string& cache, const std::string& key,
                                             const std::string& method, const nlohmann::json& dependencies) {
  fs::path folder = fs::path(cache) / key;
  if (!fs::exists(folder)) return std::nullopt;
  StoredBuild stored{folder.string(), nlohmann::json(), ""};
  fs::path record_path = folder / "build.json";
  std::ifstream stream(record_path);
  stored.record = nlohmann::json::parse(stream, nullptr, /*allow_exceptions=*/false);
  const nlohmann::json& record = stored.record;
  if (!stream || record.is_discarded() || !record.is_object()) {
    stored.problem = "build.json is missing or unreadable";
  } else if (record.value("method", "") != method || record.value("version", 0) != kBuildCacheVersion) {
    stored.problem = "build.json is of another method or cache version";
  } else if (!record.contains("dependencies") || record["dependencies"] != dependencies) {
    stored.problem = "build.json has other dependencies (a key collision or an edited folder)";
  } else if (!record.contains("prepare_seconds") || !record["prepare_seconds"].is_number() || !record.contains("files")) {
    stored.problem = "build.json lacks prepare_seconds or files";
  } else {
    try {
      if (record["files"] != build_file_checksums(folder.string())) {
        stored.problem = "a file does not match its size and checksum in build.json (truncated or damaged)";
      }
    } catch (const std::runtime_error& error) {
      stored.problem = error.what();
    }
  }
  return stored;
}

std::string BuildCacheFolder::key(const std::string& method, const nlohmann::json& dependencies) const {
  return build_cache_key(method, dependencies);
}

std::optional<BuildStore::Found> BuildCacheFolder::find(const std::string& method, const std::string& key,
                                                        const nlohmann::json& dependencies) {
  if (!tidied_) {
    make_folders(folder_);
    remove_stale_staging(folder_);
    tidied_ = true;
  }
  std::optional<StoredBuild> stored = find_stored_build(folder_, key, method, dependencies);
  if (!stored) return std::nullopt;
  Found found{stored->folder, 0.0, stored->problem};
  if (found.problem.empty()) found.prepare_seconds = stored->record["prepare_seconds"].get<double>();
  return found;
}

void BuildCacheFolder::put(const std::string& method, const std::string& key, const nlohmann::json& dependencies,
                           const ParamSet& build, double prepare_seconds, bool replace,
                           const std::function<void(const std::string& folder)>& write) {
  make_folders(folder_);
  StagingFolder staging((fs::path(folder_) / key).string());
  write(staging.path());
  nlohmann::json record = {{"method", method},
                           {"version", kBuildCacheVersion},
                           {"key", key},
                           {"dependencies", dependencies},
                           {"build", build.to_json()},
                           {"files", build_file_checksums(staging.path())},
                           {"prepare_seconds", prepare_seconds}};
  // build.json last: a folder without it is incomplete and never read.
  write_text_atomically((fs::path(staging.path()) / "build.json").string(), record.dump(2) + "\n");
  if (replace) {
    staging.commit();  // replaces the unreadable one
  } else if (!staging.commit_if_absent()) {
    // Another process stored the same build while we computed it; ours is identical in content
    // (same dependencies), so theirs serves: nothing to do.
  }
}

}  // namespace causticbench
