// A shared library that is no plugin: it exports no causticbench_plugin() (tests/test_plugins.cpp).
extern "C" __attribute__((visibility("default"))) int some_other_library_function() { return 42; }
