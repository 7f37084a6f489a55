// A plugin method with a stored build (tests/test_plugins.cpp): its prepare() counts the scene's objects
// into `level`, which it saves and loads through the build cache; its builds are keyed with the plugin's
// identity, so that a rebuilt plugin computes its build again.
#include <fstream>
#include <stdexcept>

#include "methods/plugin.h"

namespace {

using namespace causticbench;

class CachedConstant : public CausticMethod, public BuildCache {
 public:
  static const MethodInfo& static_info() {
    static const MethodInfo info = [] {
      MethodInfo m;
      m.name = "cached_constant";
      m.summary = "E_c = 0; its build (the scene's object count) goes through the build cache";
      m.params = {ParamSpec::integer("offset", 1, 0, 100, "added to the object count", ParamPhase::build)};
      return m;
    }();
    return info;
  }
  const MethodInfo& info() const override { return static_info(); }
  BuildCache* build_cache() override { return this; }
  void prepare(const PrepareContext& context, const ParamSet& build) override {
    level_ = static_cast<double>(context.scene.objects.size() + build.integer("offset"));
  }
  void update(const FrameContext&, const ParamSet&) override {}
  Image render(const GBuffer& gbuffer, const ParamSet&) override { return Image(gbuffer.width, gbuffer.height, 3); }
  size_t memory_bytes() const override { return sizeof(level_); }
  Counters counters() const override { return {}; }
  nlohmann::json record() const override { return {{"level", level_}}; }

  std::optional<nlohmann::json> build_dependencies(const PrepareContext& context, const ParamSet& build) const override {
    return nlohmann::json{{"objects", context.scene.objects.size()}, {"offset", build.integer("offset")}};
  }
  void save_build(const std::string& folder) const override { std::ofstream(folder + "/level.txt") << level_; }
  void load_build(const PrepareContext&, const ParamSet&, const std::string& folder) override {
    std::ifstream in(folder + "/level.txt");
    if (!(in >> level_)) throw std::runtime_error("level.txt unreadable");
  }

 private:
  double level_ = 0.0;
};

void register_methods(PluginRegistrar& registrar) { registrar.add(plugin_method<CachedConstant>()); }

}  // namespace

CAUSTICBENCH_PLUGIN("cached", "0.1", register_methods)
