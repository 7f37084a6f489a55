# The installable SDK (docs/sdk.md): `cmake --install build --prefix P` puts the causticbench executable
# under P/bin, the headers a method needs under P/include/causticbench (the deliberate surface: the core
# scene model, G-buffer, tracers, images, sampling; the method interface, its knobs, build store, registry
# and plugin entry point; the common helpers the built-in methods use; the quantity registry), and a CMake
# package: find_package(causticbench) gives causticbench::sdk to compile against and
# causticbench_add_plugin() to build a plugin, a shared library the executable loads (methods/plugin.h).
include(GNUInstallDirs)
include(CMakePackageConfigHelpers)

install(TARGETS causticbench RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
# What `causticbench conform` runs (tests/conformance_main.cpp), with the scenes and the capability studies
# it reads once the source tree is gone.
if(TARGET causticbench-conformance)
  install(TARGETS causticbench-conformance RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
  install(DIRECTORY ${PROJECT_SOURCE_DIR}/configs/scenes/ DESTINATION ${CMAKE_INSTALL_DATADIR}/causticbench/configs/scenes)
  install(DIRECTORY ${PROJECT_SOURCE_DIR}/assets/ DESTINATION ${CMAKE_INSTALL_DATADIR}/causticbench/assets)
  install(FILES ${PROJECT_SOURCE_DIR}/configs/experiments/study_capabilities.yaml
    ${PROJECT_SOURCE_DIR}/configs/experiments/study_capabilities_glass.yaml
    DESTINATION ${CMAKE_INSTALL_DATADIR}/causticbench/configs/experiments)
endif()
# The report's plotting bundles, which reports/report.cpp finds there once the source tree is gone.
install(DIRECTORY ${PROJECT_SOURCE_DIR}/reports/vendor/ DESTINATION ${CMAKE_INSTALL_DATADIR}/causticbench/vendor
  FILES_MATCHING PATTERN "*.js" PATTERN "LICENSE-*")
set(sdk_include ${CMAKE_INSTALL_INCLUDEDIR}/causticbench)
install(DIRECTORY ${PROJECT_SOURCE_DIR}/core/ DESTINATION ${sdk_include}/core FILES_MATCHING PATTERN "*.h")
install(DIRECTORY ${PROJECT_SOURCE_DIR}/methods/common/ DESTINATION ${sdk_include}/methods/common FILES_MATCHING PATTERN "*.h")
install(FILES
  ${PROJECT_SOURCE_DIR}/methods/method.h ${PROJECT_SOURCE_DIR}/methods/param_dict.h
  ${PROJECT_SOURCE_DIR}/methods/build_store.h ${PROJECT_SOURCE_DIR}/methods/registry.h
  ${PROJECT_SOURCE_DIR}/methods/plugin.h
  DESTINATION ${sdk_include}/methods)
install(FILES ${PROJECT_SOURCE_DIR}/metrics/quantities.h DESTINATION ${sdk_include}/metrics)

set(sdk_package ${CMAKE_INSTALL_LIBDIR}/cmake/causticbench)
configure_package_config_file(${PROJECT_SOURCE_DIR}/cmake/causticbenchConfig.cmake.in
  ${CMAKE_CURRENT_BINARY_DIR}/causticbenchConfig.cmake INSTALL_DESTINATION ${sdk_package}
  PATH_VARS CMAKE_INSTALL_INCLUDEDIR CMAKE_INSTALL_BINDIR)
write_basic_package_version_file(${CMAKE_CURRENT_BINARY_DIR}/causticbenchConfigVersion.cmake
  VERSION ${PROJECT_VERSION} COMPATIBILITY SameMinorVersion)
install(FILES ${CMAKE_CURRENT_BINARY_DIR}/causticbenchConfig.cmake ${CMAKE_CURRENT_BINARY_DIR}/causticbenchConfigVersion.cmake
  DESTINATION ${sdk_package})
