// The explicit list of built-in methods (no self-registration): methods/registry.cpp.
#pragma once

#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "methods/method.h"

namespace causticbench {

struct PluginIdentity;  // methods/plugins.h

struct MethodEntry {
  const MethodInfo& (*info)();
  std::function<std::unique_ptr<CausticMethod>()> create;
  const PluginIdentity* plugin = nullptr;  // the plugin that registered it; null for a built-in method
};

const std::vector<MethodEntry>& method_registry();
std::vector<std::string> method_names();
// The methods whose work is their own: every one but those that run a user's program
// (MethodInfo::runs_a_program). What the registry-wide suites (conformance, capabilities) cover.
std::vector<std::string> native_method_names();
// Throws InputError naming the known methods (with "did you mean") for an unknown name.
const MethodEntry& find_method(const std::string& name);
std::unique_ptr<CausticMethod> create_method(const std::string& name);
// The registered methods that have a GPU backend (CausticMethod::gpu()): those whose frame `render
// --dump-frame` can write. Asks a fresh instance of each (constructors do no work).
std::vector<std::string> methods_with_gpu_backend();

// Adds a plugin's method (methods/plugins.h checks its name first); it stays until the process ends.
void register_plugin_method(MethodEntry entry);

// For tests: adds a method to the registry (after the built-in ones) until destroyed, so that a test
// can drive a synthetic method through experiments and the runner. Not for built-in methods: those
// are the lines of registry.cpp.
class ScopedMethodRegistration {
 public:
  explicit ScopedMethodRegistration(MethodEntry entry);
  ~ScopedMethodRegistration();
  ScopedMethodRegistration(const ScopedMethodRegistration&) = delete;
  ScopedMethodRegistration& operator=(const ScopedMethodRegistration&) = delete;

 private:
  std::string name_;
};

}  // namespace causticbench
