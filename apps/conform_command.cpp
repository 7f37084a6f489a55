// `causticbench conform [--plugin PATH]... [METHOD]`: the conformance and capability checks every built-in
// method passes, run on a plugin's methods by causticbench-conformance (tests/conformance_main.cpp: the
// same suites, not a copy), with the loaded plugins handed over in CAUSTICBENCH_PLUGINS. Prints each check
// with its verdict and, for a failed one, what failed; exit code 0 when all pass, 1 when one fails.
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "apps/commands.h"
#include "core/shell.h"
#include "core/assets.h"
#include "core/errors.h"
#include "core/files.h"
#include "methods/plugins.h"
#include "methods/registry.h"
#include "store/store_files.h"

namespace causticbench {

namespace {

namespace fs = std::filesystem;

// Installed and built beside causticbench (tests/CMakeLists.txt, cmake/sdk.cmake).
fs::path conformance_executable() { return fs::path(executable_path()).parent_path() / "causticbench-conformance"; }

}  // namespace

int run_conform(const std::string& method) {
  std::vector<std::string> methods;
  if (!method.empty()) {
    find_method(method);  // an unknown name: InputError with "did you mean"
    methods.push_back(method);
  } else {
    for (const auto& plugin : loaded_plugins()) methods.insert(methods.end(), plugin->methods.begin(), plugin->methods.end());
    if (methods.empty())
      throw InputError("conform: no method to check: load a plugin with --plugin PATH (or name a method)");
  }
  const fs::path executable = conformance_executable();
  if (!fs::is_regular_file(executable))
    throw std::runtime_error(fmt::format("{} is missing: it is built with the tests (CAUSTICBENCH_TESTS=ON) and installed "
                                         "beside causticbench",
                                         executable.string()));
  std::vector<std::string> paths;
  for (const auto& plugin : loaded_plugins()) paths.push_back(plugin->path);
  std::vector<std::string> filters;
  // The suites' parameters: the method, or the method and a capability ("<method>_<capability>").
  for (const std::string& name : methods) {
    filters.push_back("*/" + name);
    for (const auto& [capability, value] : Capabilities{}.entries()) filters.push_back("*/" + name + "_" + capability);
  }
  const fs::path report = fs::temp_directory_path() / fmt::format("causticbench_conform_{}.json", getpid());
  const fs::path log = fs::temp_directory_path() / fmt::format("causticbench_conform_{}.log", getpid());
  const std::string command = fmt::format("CAUSTICBENCH_PLUGINS={} {} --gtest_filter={} --gtest_output=json:{} > {} 2>&1",
                                          shell_quoted(join(paths, ":")), shell_quoted(executable.string()),
                                          shell_quoted(join(filters, ":")), shell_quoted(report.string()),
                                          shell_quoted(log.string()));
  fmt::print("checking {} with {} (the suites every built-in method passes)\n", join(methods, ", "), executable.string());
  const int status = std::system(command.c_str());
  std::optional<std::string> text = read_file_bytes(report.string());
  const std::string output = read_file_bytes(log.string()).value_or("");
  fs::remove(report);
  fs::remove(log);
  if (!text) throw std::runtime_error(fmt::format("causticbench-conformance wrote no results (status {}):\n{}", status, output));
  const nlohmann::json results = nlohmann::json::parse(*text);
  size_t passed = 0, failed = 0, skipped = 0;
  for (const nlohmann::json& suite : results.value("testsuites", nlohmann::json::array())) {
    for (const nlohmann::json& test : suite.value("testsuite", nlohmann::json::array())) {
      const std::string name = suite.value("name", "") + "." + test.value("name", "");
      const nlohmann::json failures = test.value("failures", nlohmann::json::array());
      const bool was_skipped = test.value("result", "") == "SKIPPED";
      std::string verdict = !failures.empty() ? "FAIL" : was_skipped ? "skipped" : "pass";
      ++(!failures.empty() ? failed : was_skipped ? skipped : passed);
      fmt::print("  {:<8} {}\n", verdict, name);
      for (const nlohmann::json& failure : failures) {
        std::string message = failure.value("failure", "");
        if (message.size() > 1200) message = message.substr(0, 1200) + " ...";
        fmt::print("           {}\n", message);
      }
    }
  }
  fmt::print("{} passed, {} failed, {} skipped\n", passed, failed, skipped);
  if (passed + failed + skipped == 0) throw std::runtime_error("causticbench-conformance ran no check:\n" + output);
  return failed ? 1 : 0;
}

}  // namespace causticbench
