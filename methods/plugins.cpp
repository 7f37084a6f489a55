// Loading plugins (declared in plugins.h).
#include "methods/plugins.h"

#include <dlfcn.h>

#include <cstdlib>
#include <filesystem>
#include <set>

#include <fmt/format.h>

#include "core/assets.h"
#include "core/errors.h"
#include "core/hash.h"
#include "methods/plugin.h"
#include "methods/plugin_file.h"
#include "methods/registry.h"

namespace causticbench {

namespace {

namespace fs = std::filesystem;

std::vector<std::unique_ptr<PluginIdentity>>& plugins() {
  static std::vector<std::unique_ptr<PluginIdentity>> loaded;
  return loaded;
}

// Collects what a plugin registers, so that nothing of it enters the registry unless all of it may.
class CollectingRegistrar : public PluginRegistrar {
 public:
  void add(MethodEntry method) override { methods.push_back(std::move(method)); }
  std::vector<MethodEntry> methods;
};

// A method name as run keys, folders and filters use it: lower-case letters, digits and '_'.
bool valid_method_name(const std::string& name) {
  if (name.empty() || name.size() > 64) return false;
  for (char c : name)
    if (!((c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') || c == '_')) return false;
  return true;
}

// Who already has a method name: "the built-in method" or "plugin X (path)".
std::string owner_of(const MethodEntry& entry) {
  return entry.plugin ? fmt::format("the method of plugin {} ({})", entry.plugin->name, entry.plugin->path)
                      : "the built-in method of that name";
}

}  // namespace

nlohmann::json PluginIdentity::key_json() const { return {{"name", name}, {"version", version}, {"hash", hash}}; }

nlohmann::json PluginIdentity::to_json() const {
  nlohmann::json out = key_json();
  out["path"] = path;
  out["methods"] = methods;
  return out;
}

const std::vector<std::unique_ptr<PluginIdentity>>& loaded_plugins() { return plugins(); }

const PluginIdentity& load_plugin(const std::string& given) {
  std::error_code error;
  const fs::file_status status = fs::status(given, error);
  if (!fs::exists(status))
    throw InputError(fmt::format("plugin {}: no such file (expected a shared library built against the causticbench "
                                 "SDK, docs/sdk.md)",
                                 given));
  if (!fs::is_regular_file(status))
    throw InputError(fmt::format("plugin {}: it is {}, not a file (expected a shared library built against the "
                                 "causticbench SDK, docs/sdk.md)",
                                 given, fs::is_directory(status) ? "a folder" : "not a regular file (a FIFO, socket or device)"));
  const std::string path = fs::canonical(given).string();
  for (const auto& plugin : plugins())
    if (plugin->path == path) return *plugin;
  // A truncated library would be mapped past its end and kill the process with SIGBUS at dlopen().
  if (const std::string problem = plugin_file_problem(path); !problem.empty())
    throw InputError(fmt::format("plugin {}: cannot be loaded: {} (rebuild it against the causticbench SDK, docs/sdk.md)",
                                 path, problem));
  void* library = dlopen(path.c_str(), RTLD_NOW | RTLD_LOCAL);
  if (!library) throw InputError(fmt::format("plugin {}: cannot be loaded: {}", path, dlerror()));
  using EntryPoint = const PluginDescriptor* (*)();
  auto entry_point = reinterpret_cast<EntryPoint>(dlsym(library, "causticbench_plugin"));
  if (!entry_point) {
    dlclose(library);
    throw InputError(fmt::format("plugin {}: exports no causticbench_plugin(): not a causticbench plugin (write its entry "
                                 "point with CAUSTICBENCH_PLUGIN, methods/plugin.h; docs/sdk.md)",
                                 path));
  }
  const PluginDescriptor* descriptor = entry_point();
  // The version first: nothing else of a descriptor of another version may be read.
  if (!descriptor || descriptor->sdk_version != kSdkVersion) {
    const int found = descriptor ? descriptor->sdk_version : 0;
    dlclose(library);
    throw InputError(fmt::format("plugin {}: built against causticbench SDK version {}, but this causticbench is SDK "
                                 "version {}: rebuild the plugin against this causticbench's installed SDK",
                                 path, found, kSdkVersion));
  }
  if (descriptor->compiler_abi != kCompilerAbi) {
    dlclose(library);
    throw InputError(fmt::format("plugin {}: built with C++ ABI {} (GCC ABI version and the C++11 string ABI), but this "
                                 "causticbench uses {}: rebuild it with the compiler causticbench was built with",
                                 path, descriptor->compiler_abi, kCompilerAbi));
  }
  auto identity = std::make_unique<PluginIdentity>();
  identity->name = descriptor->name ? descriptor->name : "";
  identity->version = descriptor->version ? descriptor->version : "";
  identity->path = path;
  uint64_t bytes = 0;
  identity->hash = hash_file(path, bytes);
  const std::string which = fmt::format("plugin {} ({})", identity->name, path);
  if (identity->name.empty() || !descriptor->register_methods)
    throw InputError(fmt::format("{}: its descriptor has no name or no registration function", which));
  CollectingRegistrar registrar;
  try {
    descriptor->register_methods(registrar);
  } catch (...) {
    throw InputError(fmt::format("{}: its registration failed: {}", which, current_exception_text()));
  }
  if (registrar.methods.empty()) throw InputError(fmt::format("{}: it registers no method", which));
  std::set<std::string> names;
  for (MethodEntry& method : registrar.methods) {
    if (!method.info || !method.create) throw InputError(fmt::format("{}: a method entry without info or create", which));
    std::string name;
    try {
      name = method.info().name;
    } catch (...) {
      throw InputError(fmt::format("{}: a method's info() failed: {}", which, current_exception_text()));
    }
    if (!valid_method_name(name))
      throw InputError(fmt::format("{}: method name '{}' is not one of lower-case letters, digits and '_' (at most 64)",
                                   which, name));
    if (!names.insert(name).second) throw InputError(fmt::format("{}: it registers method '{}' twice", which, name));
    for (const MethodEntry& existing : method_registry())
      if (existing.info().name == name)
        throw InputError(fmt::format("{}: its method '{}' clashes with {}; rename it", which, name, owner_of(existing)));
  }
  for (MethodEntry& method : registrar.methods) {
    identity->methods.push_back(method.info().name);
    method.plugin = identity.get();
    register_plugin_method(std::move(method));
  }
  plugins().push_back(std::move(identity));
  return *plugins().back();
}

void load_plugins_from_environment() {
  const char* list = std::getenv("CAUSTICBENCH_PLUGINS");
  if (!list) return;
  for (const std::string& path : split_path_list(list)) {
    try {
      load_plugin(path);
    } catch (const InputError& failure) {
      throw InputError(fmt::format("CAUSTICBENCH_PLUGINS: {}", failure.what()));
    }
  }
}

}  // namespace causticbench
