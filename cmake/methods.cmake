# What a method folder's CMakeLists.txt calls besides target_sources(causticbench_methods ...) and
# causticbench_add_test (cmake/tests.cmake). See docs/adding-a-method.md.

# causticbench_add_gpu_backend(METHOD name SOURCES source... REPLAY replay.cpp FORMAT function)
#
# A method's Vulkan backend: the library causticbench_<name>_vulkan of SOURCES, which depend only on gpu/
# (so that causticbench-gpubench, which links the Vulkan loader alone, can replay its frames), linked into
# the methods library; its replay REPLAY compiled into causticbench_frame_dumps; and its FrameDumpFormat,
# returned by the function FORMAT that REPLAY defines (methods/frame_replay.h), listed for gpubench and
# gpu-compare in the generated frame_dump_formats.cpp. Add its shaders with glslc_shader on the library.
function(causticbench_add_gpu_backend)
  cmake_parse_arguments(ARG "" "METHOD;REPLAY;FORMAT" "SOURCES" ${ARGN})
  if(NOT ARG_METHOD OR NOT ARG_SOURCES OR NOT ARG_REPLAY OR NOT ARG_FORMAT)
    message(FATAL_ERROR "causticbench_add_gpu_backend: METHOD, SOURCES, REPLAY and FORMAT are all needed")
  endif()
  set(library causticbench_${ARG_METHOD}_vulkan)
  add_library(${library} STATIC ${ARG_SOURCES})
  target_include_directories(${library} PUBLIC ${PROJECT_SOURCE_DIR})
  target_link_libraries(${library} PUBLIC causticbench_gpu causticbench_frame_dump)
  target_sources(causticbench_frame_dumps PRIVATE ${CMAKE_CURRENT_SOURCE_DIR}/${ARG_REPLAY})
  target_link_libraries(causticbench_frame_dumps PUBLIC ${library})
  target_link_libraries(causticbench_methods PUBLIC ${library})
  set_property(GLOBAL APPEND PROPERTY CAUSTICBENCH_FRAME_DUMP_FORMATS ${ARG_FORMAT})
endfunction()

# Called once, after every method folder: writes frame_dump_formats.cpp from the registered formats, in
# the order the folders were added.
function(causticbench_write_frame_dump_formats)
  get_property(formats GLOBAL PROPERTY CAUSTICBENCH_FRAME_DUMP_FORMATS)
  set(declarations "")
  set(entries "")
  foreach(format IN LISTS formats)
    string(APPEND declarations "FrameDumpFormat ${format}();\n")
    string(APPEND entries "      ${format}(),\n")
  endforeach()
  set(output ${PROJECT_BINARY_DIR}/generated/frame_dump_formats.cpp)
  configure_file(${PROJECT_SOURCE_DIR}/methods/frame_dump_formats.cpp.in ${output} @ONLY)
  target_sources(causticbench_frame_dumps PRIVATE ${output})
endfunction()
