// A plugin whose registration throws (tests/test_plugins.cpp): refused, naming what it threw.
#include <stdexcept>

#include "methods/plugin.h"

namespace {
void register_methods(causticbench::PluginRegistrar&) {
  throw std::runtime_error("the licence file licence.txt is missing");
}
}  // namespace

CAUSTICBENCH_PLUGIN("throwing", "0.1", register_methods)
