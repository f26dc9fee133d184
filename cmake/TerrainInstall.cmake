# Install rules and an exported CMake package, so another application can
#   find_package(Terrain CONFIG REQUIRED)
#   target_link_libraries(app PRIVATE terrain::runtime)
# and embed the runtime. Every library terrain_add_library() made is installed and exported
# under its own name (terrain::base ... terrain::truth), with the umbrellas terrain::io and
# terrain::runtime. Shaders are compiled into terrain::programs, so an installed runtime
# needs no shader folder at run time.
include(CMakePackageConfigHelpers)

get_property(_targets GLOBAL PROPERTY TERRAIN_INSTALLED_TARGETS)
get_property(_include_dirs GLOBAL PROPERTY TERRAIN_PUBLIC_INCLUDE_DIRS)
install(TARGETS ${_targets}
  EXPORT TerrainTargets
  ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR}
  LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR}
  RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR}
  INCLUDES DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
foreach(_dir IN LISTS _include_dirs)
  install(DIRECTORY ${_dir}/ DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
endforeach()
install(DIRECTORY ${PROJECT_SOURCE_DIR}/shaders/ DESTINATION ${CMAKE_INSTALL_DATADIR}/terrain/shaders
  FILES_MATCHING PATTERN "*.glsl" PATTERN "*.vert" PATTERN "*.frag" PATTERN "*.tesc" PATTERN "*.tese"
                 PATTERN "*.geom" PATTERN "*.h")

set(_cmake_dir ${CMAKE_INSTALL_LIBDIR}/cmake/Terrain)
install(EXPORT TerrainTargets NAMESPACE terrain:: DESTINATION ${_cmake_dir})
configure_package_config_file(${PROJECT_SOURCE_DIR}/cmake/TerrainConfig.cmake.in
  ${PROJECT_BINARY_DIR}/TerrainConfig.cmake INSTALL_DESTINATION ${_cmake_dir})
write_basic_package_version_file(${PROJECT_BINARY_DIR}/TerrainConfigVersion.cmake
  COMPATIBILITY SameMinorVersion)
install(FILES ${PROJECT_BINARY_DIR}/TerrainConfig.cmake ${PROJECT_BINARY_DIR}/TerrainConfigVersion.cmake
  DESTINATION ${_cmake_dir})
