# Install rules and an exported CMake package, so another application can
#   find_package(Terrain CONFIG REQUIRED)
#   target_link_libraries(app PRIVATE terrain::runtime)
# and embed the runtime. Shaders are compiled into terrain::runtime, so an installed
# runtime needs no shader folder at run time.
include(CMakePackageConfigHelpers)

install(TARGETS terrain_io terrain_cache terrain_runtime
  EXPORT TerrainTargets
  ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR}
  LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR}
  RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR}
  INCLUDES DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
foreach(folder io cache runtime)
  install(DIRECTORY ${PROJECT_SOURCE_DIR}/${folder}/include/ DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
endforeach()
install(DIRECTORY ${PROJECT_SOURCE_DIR}/shaders/ DESTINATION ${CMAKE_INSTALL_DATADIR}/terrain/shaders
  FILES_MATCHING PATTERN "*.glsl" PATTERN "*.vert" PATTERN "*.frag" PATTERN "*.tesc" PATTERN "*.tese"
                 PATTERN "*.h")

set(_cmake_dir ${CMAKE_INSTALL_LIBDIR}/cmake/Terrain)
install(EXPORT TerrainTargets NAMESPACE terrain:: DESTINATION ${_cmake_dir})
configure_package_config_file(${PROJECT_SOURCE_DIR}/cmake/TerrainConfig.cmake.in
  ${PROJECT_BINARY_DIR}/TerrainConfig.cmake INSTALL_DESTINATION ${_cmake_dir})
write_basic_package_version_file(${PROJECT_BINARY_DIR}/TerrainConfigVersion.cmake
  COMPATIBILITY SameMinorVersion)
install(FILES ${PROJECT_BINARY_DIR}/TerrainConfig.cmake ${PROJECT_BINARY_DIR}/TerrainConfigVersion.cmake
  DESTINATION ${_cmake_dir})
