# terrain_add_library(<name> [PUBLIC_DEPS ...] [PRIVATE_DEPS ...] [EXTRA_SOURCES ...])
# One static library per folder (../shared/STYLE.md, "Layout shows the architecture"): the
# folder that calls this holds include/terrain/<ns>/ (public) and src/ (private, every .cpp
# is part of the library: one concept per file). The target is terrain_<name>, used as
# terrain::<name> in the tree and exported under that name by TerrainInstall.cmake.
#
# terrain_add_umbrella(<name> <targets>...)
# An INTERFACE target terrain::<name> that links a folder's sub-libraries (terrain::io,
# terrain::runtime), so an application links one name and gets the whole layer.

function(terrain_add_library name)
  cmake_parse_arguments(ARG "" "" "PUBLIC_DEPS;PRIVATE_DEPS;EXTRA_SOURCES" ${ARGN})
  set(_target terrain_${name})
  file(GLOB _sources CONFIGURE_DEPENDS ${CMAKE_CURRENT_SOURCE_DIR}/src/*.cpp)
  add_library(${_target} STATIC ${_sources} ${ARG_EXTRA_SOURCES})
  add_library(terrain::${name} ALIAS ${_target})
  set_target_properties(${_target} PROPERTIES EXPORT_NAME ${name})
  target_include_directories(${_target}
    PUBLIC
      $<BUILD_INTERFACE:${CMAKE_CURRENT_SOURCE_DIR}/include>
      $<INSTALL_INTERFACE:${CMAKE_INSTALL_INCLUDEDIR}>
    PRIVATE
      ${CMAKE_CURRENT_SOURCE_DIR}/src)
  target_link_libraries(${_target} PUBLIC ${ARG_PUBLIC_DEPS} PRIVATE ${ARG_PRIVATE_DEPS})
  terrain_configure_target(${_target})
  set_property(GLOBAL APPEND PROPERTY TERRAIN_INSTALLED_TARGETS ${_target})
  set_property(GLOBAL APPEND PROPERTY TERRAIN_PUBLIC_INCLUDE_DIRS ${CMAKE_CURRENT_SOURCE_DIR}/include)
endfunction()

function(terrain_add_umbrella name)
  set(_target terrain_${name})
  add_library(${_target} INTERFACE)
  add_library(terrain::${name} ALIAS ${_target})
  set_target_properties(${_target} PROPERTIES EXPORT_NAME ${name})
  target_link_libraries(${_target} INTERFACE ${ARGN})
  set_property(GLOBAL APPEND PROPERTY TERRAIN_INSTALLED_TARGETS ${_target})
endfunction()
