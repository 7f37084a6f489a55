// Assets (meshes, HDR environment maps) are named, not pathed. A name resolves through the asset
// search path: the scene file's folder, the folders in $CAUSTICBENCH_ASSET_PATH (colon separated),
// the project's assets/ folder, and the Debian data packages that scripts/setup.sh installs.
#pragma once

#include <string>
#include <vector>

#include "core/errors.h"

namespace causticbench {

struct AssetKind {
  std::string what;                     // "mesh" or "environment map"
  std::vector<std::string> extensions;  // tried in order when the name has none
};

// Built-in names for assets shipped by Debian packages, e.g. "bunny" -> glmark2-data's bunny.obj.
struct KnownAsset {
  std::string name;
  std::string relative_path;  // below one of the package folders
  std::string package;        // the Debian package that ships it
};
const std::vector<KnownAsset>& known_assets();

std::vector<std::string> asset_search_path(const std::string& scene_folder);

// The running executable's path; empty when the system does not say.
std::string executable_path();
// Where an installed causticbench keeps its data (cmake/sdk.cmake): share/causticbench beside the bin/
// folder of the running executable (assets, scenes, the report's bundles); empty when unknown.
std::string installed_data_folder();
// A colon-separated list (CAUSTICBENCH_ASSET_PATH, CAUSTICBENCH_PLUGINS): its entries, empty ones dropped.
std::vector<std::string> split_path_list(const std::string& list);

// Returns an absolute path, or throws an InputError naming the asset, the folders searched and
// where to get it.
std::string resolve_asset(const std::string& name, const AssetKind& kind, const std::string& scene_folder,
                          const SourceLocation& where);

}  // namespace causticbench
