// Loading plugins (methods/plugin.h, docs/sdk.md): the host's side. A plugin is loaded once per process
// and never unloaded (its methods live in the registry until the process ends). Every refusal is an
// InputError (exit code 2) that names the library and what is wrong, raised before any of its methods is
// registered and before any work starts.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace causticbench {

// Which build of a plugin a run measured: part of its methods' run keys and build keys, so that a rebuilt
// plugin is measured again.
struct PluginIdentity {
  std::string name, version;
  std::string path;  // as loaded (absolute)
  std::string hash;  // xxHash64 of the library file
  std::vector<std::string> methods;
  // {name, version, hash}: what keys hash (not the path: a plugin moved keeps its runs).
  nlohmann::json key_json() const;
  // key_json with the path and methods.
  nlohmann::json to_json() const;
};

// Loads the plugin at `path` (the same file twice: once) and registers its methods. Refused: a missing
// or unloadable file, no causticbench_plugin(), another SDK version or compiler ABI, a registration that
// throws, a method without a valid name or one whose name another method has.
const PluginIdentity& load_plugin(const std::string& path);

// The plugins of CAUSTICBENCH_PLUGINS (paths separated by ':'), when it is set.
void load_plugins_from_environment();

const std::vector<std::unique_ptr<PluginIdentity>>& loaded_plugins();

}  // namespace causticbench
