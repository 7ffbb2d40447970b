# cmake --install: the C++ package (component `cpp`) and the flexure command (component `cli`).
#   <prefix>/include/flexure/<layer>/*.h            the headers, included as "<layer>/x.h"
#   <prefix>/lib/libflexure_<layer>.a               the library layers
#   <prefix>/lib/cmake/flexure/flexureConfig.cmake  find_package(flexure): flexure::modeling,
#       flexure::curvature, flexure::optimize, flexure::render, flexure::reports and the umbrella
#       flexure::flexure (all five)
#   <prefix>/bin/flexure                            the command
# The Python module installs into Python's own platlib (component `python`, python/CMakeLists.txt),
# whatever the prefix; `cmake --install build --prefix DIR --component cpp` installs only the package.
include(CMakePackageConfigHelpers)

# The umbrella: every layer (flexure is the command's target name, so this one is named apart).
add_library(flexure_library INTERFACE)
target_link_libraries(flexure_library INTERFACE flexure_reports flexure_optimize flexure_render
                                                flexure_curvature flexure_modeling)
set_target_properties(flexure_library PROPERTIES EXPORT_NAME flexure)
add_library(flexure::flexure ALIAS flexure_library)

set(flexure_layers modeling curvature optimize render reports)
foreach(layer ${flexure_layers})
  list(APPEND flexure_layer_targets flexure_${layer})
endforeach()
install(TARGETS ${flexure_layer_targets} flexure_library EXPORT flexureTargets
        ARCHIVE DESTINATION lib COMPONENT cpp)
install(DIRECTORY ${flexure_layers} DESTINATION include/flexure COMPONENT cpp
        FILES_MATCHING PATTERN "*.h")
install(EXPORT flexureTargets NAMESPACE flexure:: DESTINATION lib/cmake/flexure COMPONENT cpp)

configure_package_config_file(cmake/flexureConfig.cmake.in
                              ${CMAKE_CURRENT_BINARY_DIR}/flexureConfig.cmake
                              INSTALL_DESTINATION lib/cmake/flexure)
# 0.x: a minor version may change the API, so only the same major.minor is compatible.
write_basic_package_version_file(${CMAKE_CURRENT_BINARY_DIR}/flexureConfigVersion.cmake
                                 COMPATIBILITY SameMinorVersion)
install(FILES ${CMAKE_CURRENT_BINARY_DIR}/flexureConfig.cmake
              ${CMAKE_CURRENT_BINARY_DIR}/flexureConfigVersion.cmake
              cmake/flexureLibraries.cmake
        DESTINATION lib/cmake/flexure COMPONENT cpp)

install(TARGETS flexure RUNTIME DESTINATION bin COMPONENT cli)
