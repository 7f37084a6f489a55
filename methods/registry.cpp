#include "methods/registry.h"

#include <algorithm>

#include <fmt/format.h>

#include "methods/caustic_mapping/caustic_mapping.h"
#include "methods/caustic_volume/caustic_volume.h"
#include "methods/external/external.h"
#include "methods/prt/prt.h"
#include "methods/csl/csl.h"
#include "methods/lpi/lpi.h"
#include "methods/photon_map/photon_map.h"
#include "methods/pinhole/pinhole.h"
#include "methods/reference/reference.h"
#include "methods/rt_photons/rt_photons.h"

namespace causticbench {

namespace {
template <typename Method>
MethodEntry entry() {
  return MethodEntry{&Method::static_info, [] { return std::make_unique<Method>(); }};
}

std::vector<MethodEntry>& mutable_registry() {
  // One line per method. Add yours here (see docs/adding-a-method.md).
  static std::vector<MethodEntry> registry = {
      entry<ReferenceMethod>(),
      entry<PhotonMapMethod>(),
      entry<PinholeMethod>(),
      entry<LpiMethod>(),
      entry<CslMethod>(),
      entry<CausticMappingMethod>(),
      entry<CausticVolumeMethod>(),
      entry<PrtMethod>(),
      entry<RtPhotonsMethod>(),
      entry<ExternalMethod>(),
  };
  return registry;
}

}  // namespace

const std::vector<MethodEntry>& method_registry() { return mutable_registry(); }

void register_plugin_method(MethodEntry entry) { mutable_registry().push_back(std::move(entry)); }

ScopedMethodRegistration::ScopedMethodRegistration(MethodEntry method) : name_(method.info().name) {
  for (const MethodEntry& existing : mutable_registry()) {
    if (existing.info().name == name_) throw std::logic_error("method '" + name_ + "' is registered already");
  }
  mutable_registry().push_back(std::move(method));
}

ScopedMethodRegistration::~ScopedMethodRegistration() {
  auto& registry = mutable_registry();
  registry.erase(std::remove_if(registry.begin(), registry.end(),
                                [&](const MethodEntry& method) { return method.info().name == name_; }),
                 registry.end());
}

std::vector<std::string> method_names() {
  std::vector<std::string> names;
  for (const MethodEntry& method : method_registry()) names.push_back(method.info().name);
  return names;
}

std::vector<std::string> native_method_names() {
  std::vector<std::string> names;
  for (const MethodEntry& method : method_registry())
    if (!method.info().runs_a_program) names.push_back(method.info().name);
  return names;
}

const MethodEntry& find_method(const std::string& name) {
  for (const MethodEntry& method : method_registry()) {
    if (method.info().name == name) return method;
  }
  throw InputError(fmt::format("unknown method '{}'{}; known methods: {}", name, did_you_mean(name, method_names()),
                               join(method_names(), ", ")));
}

std::unique_ptr<CausticMethod> create_method(const std::string& name) {
  const MethodEntry& entry = find_method(name);
  try {
    std::unique_ptr<CausticMethod> method = entry.create();
    if (!method) throw MethodError(fmt::format("method {}: its create() returned no instance", name));
    return method;
  } catch (const MethodError&) {
    throw;
  } catch (...) {
    // A plugin's constructor: whatever it throws fails the runs of the method, not the process.
    throw MethodError(fmt::format("constructing method {}: {}", name, current_exception_text()));
  }
}

std::vector<std::string> methods_with_gpu_backend() {
  std::vector<std::string> names;
  for (const MethodEntry& method : method_registry())
    try {
      if (create_method(method.info().name)->gpu()) names.push_back(method.info().name);
    } catch (const MethodError&) {
      // A plugin whose constructor fails has no backend to list; its own runs say why.
    }
  return names;
}

}  // namespace causticbench
