// A plugin whose methods break the interface where a careless one would (tests/test_plugins.cpp): one
// returns an image of a quarter of the G-buffer's size, one throws an int from render(), one throws a
// string from its constructor. Each run of them must fail alone, with a message, and the methods after
// them must still run: none may corrupt memory or end the process.
#include <string>

#include "methods/plugin.h"

namespace {

using causticbench::GBuffer;
using causticbench::Image;
using causticbench::MethodInfo;
using causticbench::ParamSet;

MethodInfo hostile_info(const char* name, const char* summary) {
  MethodInfo m;
  m.name = name;
  m.summary = summary;
  m.capabilities.refraction = m.capabilities.directional_light = true;
  return m;
}

class Hostile : public causticbench::CausticMethod {
 public:
  void prepare(const causticbench::PrepareContext&, const ParamSet&) override {}
  void update(const causticbench::FrameContext&, const ParamSet&) override {}
  size_t memory_bytes() const override { return 0; }
  causticbench::Counters counters() const override { return {}; }
};

class Shrunken : public Hostile {
 public:
  static const MethodInfo& static_info() {
    static const MethodInfo info = hostile_info("shrunken", "E_c of half the G-buffer's width and height");
    return info;
  }
  const MethodInfo& info() const override { return static_info(); }
  Image render(const GBuffer& gbuffer, const ParamSet&) override { return Image(gbuffer.width / 2, gbuffer.height / 2, 3, 1.0f); }
};

class IntThrower : public Hostile {
 public:
  static const MethodInfo& static_info() {
    static const MethodInfo info = hostile_info("int_thrower", "throws 42 from render()");
    return info;
  }
  const MethodInfo& info() const override { return static_info(); }
  Image render(const GBuffer&, const ParamSet&) override { throw 42; }
};

class ConstructorThrower : public Hostile {
 public:
  ConstructorThrower() { throw std::string("no licence"); }
  static const MethodInfo& static_info() {
    static const MethodInfo info = hostile_info("constructor_thrower", "throws a std::string from its constructor");
    return info;
  }
  const MethodInfo& info() const override { return static_info(); }
  Image render(const GBuffer& gbuffer, const ParamSet&) override { return Image(gbuffer.width, gbuffer.height, 3, 0.0f); }
};

void register_methods(causticbench::PluginRegistrar& registrar) {
  registrar.add(causticbench::plugin_method<Shrunken>());
  registrar.add(causticbench::plugin_method<IntThrower>());
  registrar.add(causticbench::plugin_method<ConstructorThrower>());
}

}  // namespace

CAUSTICBENCH_PLUGIN("hostile", "0.1", register_methods)
