#include <algorithm>

#include <fmt/format.h>

#include "apps/commands.h"
#include "core/scene.h"
#include "experiments/experiment.h"
#include "methods/describe.h"
#include "methods/plugins.h"
#include "methods/registry.h"

namespace causticbench {

int run_list() {
  const auto& registry = method_registry();
  std::vector<std::string> capability_names;
  for (const auto& [name, value] : Capabilities{}.entries()) capability_names.push_back(name);
  // Columns as wide as their longest entry, so that a long method name (a plugin's) keeps them aligned.
  size_t name_width = 0, capability_width = 0;
  for (const MethodEntry& method : registry) name_width = std::max(name_width, method.info().name.size());
  for (const std::string& name : capability_names) capability_width = std::max(capability_width, name.size());
  fmt::print("Methods ({}):\n", registry.size());
  for (const MethodEntry& method : registry) {
    const MethodInfo& info = method.info();
    fmt::print("  {:<{}} {}{}\n", info.name, name_width, info.summary,
               method.plugin ? fmt::format(" [plugin {} {}, {}]", method.plugin->name, method.plugin->version,
                                           method.plugin->path)
                             : "");
  }
  fmt::print("\nCapabilities (yes / no):\n  {:<{}}", "", capability_width);
  for (const MethodEntry& method : registry) fmt::print(" {:>{}}", method.info().name, std::max<size_t>(3, method.info().name.size()));
  fmt::print("\n");
  for (size_t i = 0; i < capability_names.size(); ++i) {
    fmt::print("  {:<{}}", capability_names[i], capability_width);
    for (const MethodEntry& method : registry) {
      fmt::print(" {:>{}}", method.info().capabilities.entries()[i].second ? "yes" : "no",
                 std::max<size_t>(3, method.info().name.size()));
    }
    fmt::print("\n");
  }
  return 0;
}

int run_describe(const std::string& name, bool markdown, bool quick_knobs) {
  const MethodInfo& info = find_method(name).info();
  if (quick_knobs) {
    for (const std::string& knob : info.quick_knobs) fmt::print("{}\n", knob);
    return 0;
  }
  fmt::print("{}", markdown ? describe_markdown(info) : describe_text(info));
  if (const PluginIdentity* plugin = find_method(name).plugin; plugin && !markdown)
    fmt::print("\nFrom plugin {} {} ({}, xxhash {}).\n", plugin->name, plugin->version, plugin->path, plugin->hash);
  return 0;
}

int run_validate(const std::string& file) {
  // An experiment names its methods; a scene does not.
  if (ConfigNode::load_file(file).has("methods")) {
    Experiment experiment = load_experiment(file);
    fmt::print("{}: valid experiment '{}': scene {}, {} variant(s), {} run(s), {} frame(s), {} repetition(s)\n", file,
               experiment.name, experiment.scene_path, experiment.variants.size(), experiment.runs.size(),
               experiment.frames.size(), experiment.repetitions);
    return 0;
  }
  Scene scene = load_scene(file);
  size_t specular = 0;
  for (const SceneObject& object : scene.objects) specular += object.material.is_specular() ? 1 : 0;
  fmt::print("{}: valid scene '{}': {}x{} camera, {} light(s), {} object(s) ({} specular), {} frame(s)\n", file,
             scene.name, scene.camera.width, scene.camera.height, scene.lights.size(), scene.objects.size(), specular,
             scene.frames);
  return 0;
}

}  // namespace causticbench
