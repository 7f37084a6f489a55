// Where the lifecycle driver (methods/lifecycle.h) keeps a method's build between runs and processes:
// an interface the methods layer declares and the result store implements on disk
// (store/build_cache.h, results/builds/<key>/), so that the lifecycle needs nothing above it.
#pragma once

#include <functional>
#include <optional>
#include <string>

#include <nlohmann/json.hpp>

#include "methods/param_dict.h"

namespace causticbench {

class BuildStore {
 public:
  virtual ~BuildStore() = default;

  // A build as found under its key: the folder to load it from and the seconds prepare() took when it
  // was computed, or, when it cannot be used, why (`problem` not empty).
  struct Found {
    std::string folder;
    double prepare_seconds = 0.0;
    std::string problem;
  };

  // The key of a method's build with these dependencies (CausticMethod::build_cache()->build_dependencies).
  virtual std::string key(const std::string& method, const nlohmann::json& dependencies) const = 0;
  // What is stored under `key`; std::nullopt when nothing is.
  virtual std::optional<Found> find(const std::string& method, const std::string& key,
                                    const nlohmann::json& dependencies) = 0;
  // Stores a computed build: `write(folder)` writes the method's files into an empty folder, which then
  // appears under `key` complete or not at all. `replace`: an unusable copy is there and is replaced;
  // otherwise a copy another process stored meanwhile is kept (the same dependencies: the same content).
  virtual void put(const std::string& method, const std::string& key, const nlohmann::json& dependencies,
                   const ParamSet& build, double prepare_seconds, bool replace,
                   const std::function<void(const std::string& folder)>& write) = 0;
};

}  // namespace causticbench
