// Methods built outside the tree (docs/sdk.md). A plugin is a shared library that exports one function,
//
//   extern "C" const causticbench::PluginDescriptor* causticbench_plugin();
//
// written by the CAUSTICBENCH_PLUGIN macro below. causticbench loads it (`--plugin PATH`, an experiment's
// `plugins:` list, or CAUSTICBENCH_PLUGINS), reads the descriptor's SDK version before anything else and
// refuses a library built against another, then lets it register its methods, which are then listed,
// described, rendered, run, cached and reported like the built-in ones. Part of the installed SDK.
#pragma once

#include "methods/registry.h"

namespace causticbench {

// The SDK's version: raised whenever what crosses the boundary changes its layout or meaning (the
// method interface, the registry entry, the headers docs/sdk.md lists). A plugin built against another
// version is refused with both numbers. 2: text knobs and knob families (ParamSpec::family,
// ParamType::text) and MethodInfo::runs_a_program. 3: the caustic photon tracer's layout and PathClass
// (core/photon_tracer.h: the occlusion split's blocked paths and receiver boxes; the receiver class).
inline constexpr int kSdkVersion = 3;
// The C++ ABI of the compiler and standard library: classes cross the boundary by value.
inline constexpr int kCompilerAbi = __GXX_ABI_VERSION * 10 + _GLIBCXX_USE_CXX11_ABI;

// What a plugin's registration function is handed: add() once per method.
class PluginRegistrar {
 public:
  virtual ~PluginRegistrar() = default;
  virtual void add(MethodEntry method) = 0;
};

// The one thing a plugin exports. Its first member stays the SDK version in every version, so that the
// host can read it from a plugin of any version before trusting the rest.
struct PluginDescriptor {
  int sdk_version;
  int compiler_abi;
  const char* name;     // the plugin's name, e.g. "fixed_radius_splat"
  const char* version;  // its own version, e.g. "1.0"
  void (*register_methods)(PluginRegistrar& registrar);
};

// A method of a plugin, registered like a line of methods/registry.cpp.
template <typename Method>
MethodEntry plugin_method() {
  return MethodEntry{&Method::static_info, [] { return std::make_unique<Method>(); }};
}

}  // namespace causticbench

// Defines the entry point: CAUSTICBENCH_PLUGIN("my_plugin", "1.0", register_my_methods), where
// `void register_my_methods(causticbench::PluginRegistrar&)` adds the plugin's methods.
#define CAUSTICBENCH_PLUGIN(NAME, VERSION, REGISTER)                                                         \
  extern "C" __attribute__((visibility("default"))) const ::causticbench::PluginDescriptor* causticbench_plugin() { \
    static const ::causticbench::PluginDescriptor descriptor{::causticbench::kSdkVersion,                     \
                                                             ::causticbench::kCompilerAbi, NAME, VERSION, REGISTER}; \
    return &descriptor;                                                                                        \
  }
