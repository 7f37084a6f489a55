# causticbench_add_test(NAME SOURCES... [CORE_ONLY] [EXTRA_SOURCES ...])
#
# One test executable, discovered by CTest test by test. Called from tests/ for what is about no single
# method, and from a method's own folder for its tests (methods/<m>/tests/), so that a method owns them:
# adding a method touches nothing outside its folder but the registry line and `add_subdirectory`.
# Relative SOURCES resolve against the calling folder. By default the executable links the test support
# library (tests/test_support.h: every method, the experiments, the reports) and knows the causticbench
# and causticbench-gpubench executables and the shipped scenes; CORE_ONLY links the core library alone,
# so that the test builds while the method and experiment libraries change.
function(causticbench_add_test name)
  if(NOT CAUSTICBENCH_TESTS)
    return()
  endif()
  cmake_parse_arguments(ARG "CORE_ONLY" "" "" ${ARGN})
  add_executable(${name} ${ARG_UNPARSED_ARGUMENTS})
  target_include_directories(${name} PRIVATE ${PROJECT_SOURCE_DIR})
  # Every test executable in build/tests/, wherever it is declared, so that its path stays build/tests/<name>.
  set_target_properties(${name} PROPERTIES RUNTIME_OUTPUT_DIRECTORY ${PROJECT_BINARY_DIR}/tests)
  if(ARG_CORE_ONLY)
    target_link_libraries(${name} PRIVATE causticbench_core GTest::gtest GTest::gtest_main)
  else()
    target_link_libraries(${name} PRIVATE causticbench_test_support)
    target_compile_definitions(${name} PRIVATE
      CAUSTICBENCH_BINARY="$<TARGET_FILE:causticbench>"
      CAUSTICBENCH_GPUBENCH="$<TARGET_FILE:causticbench-gpubench>"
      CAUSTICBENCH_SCENES="${PROJECT_SOURCE_DIR}/configs/scenes")
    add_dependencies(${name} causticbench causticbench-gpubench)
  endif()
  gtest_discover_tests(${name} DISCOVERY_TIMEOUT 60 PROPERTIES TIMEOUT 600)
endfunction()
