#include "core/assets.h"

#include <algorithm>
#include <cstdlib>
#include <filesystem>

#include <fmt/format.h>

namespace causticbench {

namespace fs = std::filesystem;

const std::vector<KnownAsset>& known_assets() {
  static const std::vector<KnownAsset> assets = {
      {"bunny", "glmark2/models/bunny.obj", "glmark2-data"},
      {"forest", "blender/datafiles/studiolights/world/forest.exr", "blender-data"},
      {"city", "blender/datafiles/studiolights/world/city.exr", "blender-data"},
      {"courtyard", "blender/datafiles/studiolights/world/courtyard.exr", "blender-data"},
      {"interior", "blender/datafiles/studiolights/world/interior.exr", "blender-data"},
      {"night", "blender/datafiles/studiolights/world/night.exr", "blender-data"},
      {"studio", "blender/datafiles/studiolights/world/studio.exr", "blender-data"},
      {"sunrise", "blender/datafiles/studiolights/world/sunrise.exr", "blender-data"},
      {"sunset", "blender/datafiles/studiolights/world/sunset.exr", "blender-data"},
  };
  return assets;
}

std::string executable_path() {
  std::error_code error;
  const std::filesystem::path path = std::filesystem::read_symlink("/proc/self/exe", error);
  return error ? std::string() : path.string();
}

std::string installed_data_folder() {
  const std::string executable = executable_path();
  if (executable.empty()) return "";
  return (std::filesystem::path(executable).parent_path().parent_path() / "share" / "causticbench").string();
}

std::vector<std::string> split_path_list(const std::string& list) {
  std::vector<std::string> entries;
  size_t start = 0;
  while (start <= list.size()) {
    const size_t end = std::min(list.find(':', start), list.size());
    if (end > start) entries.push_back(list.substr(start, end - start));
    start = end + 1;
  }
  return entries;
}

std::vector<std::string> asset_search_path(const std::string& scene_folder) {
  std::vector<std::string> folders;
  if (!scene_folder.empty()) folders.push_back(scene_folder);
  if (const char* extra = std::getenv("CAUSTICBENCH_ASSET_PATH"))
    for (const std::string& folder : split_path_list(extra)) folders.push_back(folder);
#ifdef CAUSTICBENCH_SOURCE_DIR
  folders.push_back(std::string(CAUSTICBENCH_SOURCE_DIR) + "/assets");
#endif
  // An installed causticbench (cmake/sdk.cmake).
  if (const std::string installed = installed_data_folder(); !installed.empty()) folders.push_back(installed + "/assets");
  folders.push_back("/usr/share");
  folders.push_back("/usr/local/share");
  return folders;
}

std::string resolve_asset(const std::string& name, const AssetKind& kind, const std::string& scene_folder,
                          const SourceLocation& where) {
  std::vector<std::string> folders = asset_search_path(scene_folder);
  std::vector<std::string> candidates;
  const KnownAsset* known = nullptr;
  for (const KnownAsset& asset : known_assets()) {
    if (asset.name == name) known = &asset;
  }
  if (known) candidates.push_back(known->relative_path);
  candidates.push_back(name);
  if (fs::path(name).extension().empty()) {
    for (const std::string& extension : kind.extensions) candidates.push_back(name + extension);
  }
  if (fs::path(name).is_absolute()) {
    if (fs::is_regular_file(name)) return name;
  } else {
    for (const std::string& folder : folders) {
      for (const std::string& candidate : candidates) {
        fs::path path = fs::path(folder) / candidate;
        if (fs::is_regular_file(path)) return fs::absolute(path).lexically_normal().string();
      }
    }
  }
  std::vector<std::string> known_names;
  for (const KnownAsset& asset : known_assets()) known_names.push_back(asset.name);
  std::string hint = known ? fmt::format("; it is shipped by the Debian package '{}': run scripts/setup.sh "
                                         "(or apt-get install {})",
                                         known->package, known->package)
                           : fmt::format("; put the file in one of those folders or in $CAUSTICBENCH_ASSET_PATH{}",
                                         did_you_mean(name, known_names));
  throw InputError(fmt::format("{}: {} asset '{}' not found; searched {}{}", where.describe(), kind.what, name,
                               join(folders, ", "), hint));
}

}  // namespace causticbench
