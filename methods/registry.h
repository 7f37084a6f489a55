// The explicit list of built-in methods (no self-registration): methods/registry.cpp.
#pragma once

#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "methods/method.h"

namespace causticbench {

struct MethodEntry {
  const MethodInfo& (*info)();
  std::function<std::unique_ptr<CausticMethod>()> create;
};

const std::vector<MethodEntry>& method_registry();
std::vector<std::string> method_names();
// Throws InputError naming the known methods (with "did you mean") for an unknown name.
const MethodEntry& find_method(const std::string& name);
std::unique_ptr<CausticMethod> create_method(const std::string& name);

}  // namespace causticbench
