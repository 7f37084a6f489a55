// A plugin whose method breaks the interface's promises (tests/test_plugins.cpp): it lights every pixel,
// receivers or not, with a constant, and declares capabilities it does not have. `causticbench conform`
// must say which checks it fails.
#include "methods/plugin.h"

namespace {

class Floodlight : public causticbench::CausticMethod {
 public:
  static const causticbench::MethodInfo& static_info() {
    static const causticbench::MethodInfo info = [] {
      causticbench::MethodInfo m;
      m.name = "floodlight";
      m.summary = "E_c = 1 W/m^2 everywhere: a method that conforms to nothing";
      m.params = {causticbench::ParamSpec::real("level", 1.0, 0.0, 10.0, "the constant it writes",
                                                causticbench::ParamPhase::render)};
      m.capabilities.reflection = m.capabilities.refraction = m.capabilities.directional_light = true;
      return m;
    }();
    return info;
  }
  const causticbench::MethodInfo& info() const override { return static_info(); }
  void prepare(const causticbench::PrepareContext&, const causticbench::ParamSet&) override {}
  void update(const causticbench::FrameContext&, const causticbench::ParamSet&) override {}
  causticbench::Image render(const causticbench::GBuffer& gbuffer, const causticbench::ParamSet& render) override {
    return causticbench::Image(gbuffer.width, gbuffer.height, 3, static_cast<float>(render.real("level")));
  }
  size_t memory_bytes() const override { return 0; }
  causticbench::Counters counters() const override { return {}; }
};

void register_methods(causticbench::PluginRegistrar& registrar) {
  registrar.add(causticbench::plugin_method<Floodlight>());
}

}  // namespace

CAUSTICBENCH_PLUGIN("floodlight", "0.1", register_methods)
