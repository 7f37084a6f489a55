// A plugin built against another SDK version (tests/test_plugins.cpp): refused before anything of it runs.
#include "methods/plugin.h"

namespace {
void register_nothing(causticbench::PluginRegistrar&) { throw std::logic_error("must never be called"); }
}  // namespace

extern "C" __attribute__((visibility("default"))) const causticbench::PluginDescriptor* causticbench_plugin() {
  static const causticbench::PluginDescriptor descriptor{causticbench::kSdkVersion + 998, causticbench::kCompilerAbi,
                                                         "from_the_future", "9.9", register_nothing};
  return &descriptor;
}
