# sphforge_add_plugin(NAME SOURCES src.cpp... [LIBRARIES lib...] [OUTPUT_DIRECTORY dir] [NO_INSTALL])
# NO_INSTALL: for test-only plugins, which must never reach an installed plugin folder.
# Builds the shared library sphforge_NAME.so that the loader finds by the plugin's name.
# A plugin needs only the public headers (core/include/sphforge) and libsphforge_core.
function(sphforge_add_plugin name)
  cmake_parse_arguments(P "NO_INSTALL" "OUTPUT_DIRECTORY" "SOURCES;LIBRARIES" ${ARGN})
  if(NOT P_SOURCES)
    message(FATAL_ERROR "sphforge_add_plugin(${name}): SOURCES is required")
  endif()
  if(NOT P_OUTPUT_DIRECTORY)
    set(P_OUTPUT_DIRECTORY "${SPHFORGE_PLUGIN_BUILD_DIR}")
  endif()
  set(target sphforge_plugin_${name})
  add_library(${target} MODULE ${P_SOURCES})
  target_link_libraries(${target} PRIVATE sphforge::core ${P_LIBRARIES})
  if(TARGET OpenMP::OpenMP_CXX)
    target_link_libraries(${target} PRIVATE OpenMP::OpenMP_CXX)
  endif()
  set_target_properties(${target} PROPERTIES
    PREFIX ""
    OUTPUT_NAME "sphforge_${name}"
    LIBRARY_OUTPUT_DIRECTORY "${P_OUTPUT_DIRECTORY}"
    CXX_VISIBILITY_PRESET hidden
    VISIBILITY_INLINES_HIDDEN ON
    INSTALL_RPATH "$ORIGIN/../..")
  if(NOT P_NO_INSTALL)
    install(TARGETS ${target} LIBRARY DESTINATION "${SPHFORGE_PLUGIN_INSTALL_DIR}")
    set_property(GLOBAL APPEND PROPERTY SPHFORGE_PLUGIN_TARGETS ${target})
  endif()
endfunction()
