// causticbench-conformance: the conformance checks (tests/test_conformance.cpp) and the capability checks
// (tests/test_capabilities.cpp) that every built-in method passes, in one executable that `causticbench
// conform --plugin PATH [METHOD]` runs on a plugin's methods: the same code, not a copy. The plugins of
// CAUSTICBENCH_PLUGINS are loaded before Google Test instantiates its suites over method_names(), so that
// their methods are among the parameters.
#include <cstdio>

#include <gtest/gtest.h>

#include "core/errors.h"
#include "methods/plugins.h"

int main(int argc, char** argv) {
  try {
    causticbench::load_plugins_from_environment();
  } catch (const causticbench::InputError& error) {
    std::fprintf(stderr, "error: %s\n", error.what());
    return 2;
  }
  ::testing::InitGoogleTest(&argc, argv);
  return RUN_ALL_TESTS();
}
