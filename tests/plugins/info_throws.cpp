// A plugin whose method's info() throws an int (tests/test_plugins.cpp): refused with exit code 2 when it
// is loaded, by every command, naming what it threw.
#include "methods/plugin.h"

namespace {

class InfoThrows : public causticbench::CausticMethod {
 public:
  static const causticbench::MethodInfo& static_info() { throw 7; }
  const causticbench::MethodInfo& info() const override { return static_info(); }
  void prepare(const causticbench::PrepareContext&, const causticbench::ParamSet&) override {}
  void update(const causticbench::FrameContext&, const causticbench::ParamSet&) override {}
  causticbench::Image render(const causticbench::GBuffer& gbuffer, const causticbench::ParamSet&) override {
    return causticbench::Image(gbuffer.width, gbuffer.height, 3, 0.0f);
  }
  size_t memory_bytes() const override { return 0; }
  causticbench::Counters counters() const override { return {}; }
};

void register_methods(causticbench::PluginRegistrar& registrar) { registrar.add(causticbench::plugin_method<InfoThrows>()); }

}  // namespace

CAUSTICBENCH_PLUGIN("info_throws", "0.1", register_methods)
