// The build cache: what a method's prepare() computed, stored under <cache>/<key>/ and reused across
// runs, variants, experiments and processes. The key is a hash of the method's name, the cache format
// version and the method's build_dependencies() (never the camera, the receivers or the variant).
//
// A stored build is a folder written into a staging folder and renamed into place
// (core/staging_folder.h): it appears complete or not at all. Its build.json, written last, holds the
// method, the dependencies (compared on load, so a hash collision or a hand-edited folder is caught),
// the size and xxHash64 of every other file of the folder (checked before the method reads them, so a
// truncated or damaged file is recomputed rather than trusted), and the seconds prepare() took. Two processes that need the same missing build both compute it;
// the first rename wins, the other discards its copy and uses the winner's. A stored build that fails
// to load is recomputed with a warning and replaced atomically.
#pragma once

#include <optional>
#include <string>
#include <utility>

#include <nlohmann/json.hpp>

#include "methods/build_store.h"

namespace causticbench {

// Raise when the layout of build.json or of the cache changes: older builds are then recomputed.
constexpr int kBuildCacheVersion = 1;

std::string build_cache_key(const std::string& method, const nlohmann::json& dependencies);

struct StoredBuild {
  std::string folder;
  nlohmann::json record;  // build.json
  std::string problem;    // why it cannot be used (unreadable, other dependencies, a damaged file); empty: usable
};

// Size and xxHash64 of every file in `folder` except build.json: {"name": {"bytes": n, "xxhash": "..."}}.
nlohmann::json build_file_checksums(const std::string& folder);

// std::nullopt when nothing is stored under `key`. Otherwise the stored build, usable when its build.json
// is complete, names the same method, version and dependencies, and its files match their checksums;
// `problem` says what is wrong when not.
std::optional<StoredBuild> find_stored_build(const std::string& cache, const std::string& key,
                                             const std::string& method, const nlohmann::json& dependencies);

// The build cache in a folder (results/builds): the BuildStore the lifecycle driver loads and stores
// builds through (methods/lifecycle.h, prepare_method).
class BuildCacheFolder : public BuildStore {
 public:
  explicit BuildCacheFolder(std::string folder) : folder_(std::move(folder)) {}
  const std::string& folder() const { return folder_; }
  std::string key(const std::string& method, const nlohmann::json& dependencies) const override;
  std::optional<Found> find(const std::string& method, const std::string& key, const nlohmann::json& dependencies) override;
  // build.json is written last, into a staging folder renamed into place (core/staging_folder.h).
  void put(const std::string& method, const std::string& key, const nlohmann::json& dependencies, const ParamSet& build,
           double prepare_seconds, bool replace, const std::function<void(const std::string& folder)>& write) override;

 private:
  std::string folder_;
  bool tidied_ = false;  // staging folders of dead processes removed
};

}  // namespace causticbench
