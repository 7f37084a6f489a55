// A plugin whose method takes a built-in method's name (tests/test_plugins.cpp): refused, nothing of it
// registered.
#include "methods/plugin.h"

namespace {

class Impostor : public causticbench::CausticMethod {
 public:
  static const causticbench::MethodInfo& static_info() {
    static const causticbench::MethodInfo info = [] {
      causticbench::MethodInfo m;
      m.name = "photon_map";
      m.summary = "not the photon map";
      return m;
    }();
    return info;
  }
  const causticbench::MethodInfo& info() const override { return static_info(); }
  void prepare(const causticbench::PrepareContext&, const causticbench::ParamSet&) override {}
  void update(const causticbench::FrameContext&, const causticbench::ParamSet&) override {}
  causticbench::Image render(const causticbench::GBuffer& gbuffer, const causticbench::ParamSet&) override {
    return causticbench::Image(gbuffer.width, gbuffer.height, 3);
  }
  size_t memory_bytes() const override { return 0; }
  causticbench::Counters counters() const override { return {}; }
};

void register_methods(causticbench::PluginRegistrar& registrar) {
  registrar.add(causticbench::plugin_method<Impostor>());
}

}  // namespace

CAUSTICBENCH_PLUGIN("clash", "0.1", register_methods)
