# Every third-party package comes from Debian 12 (scripts/setup.sh installs them).
# No vendored copies, no downloads at configure time.
find_package(Threads REQUIRED)
find_package(OpenImageIO CONFIG REQUIRED)
find_package(TIFF REQUIRED)                # GeoTIFF tags, which OpenImageIO cannot write
find_package(OpenEXR CONFIG REQUIRED)
find_package(GDAL CONFIG REQUIRED)           # netCDF, VRT mosaics, DTED, ... behind DemReader
find_package(ZLIB REQUIRED)                # CRC-32 of pyramid tiles
find_package(GeographicLib REQUIRED)       # Debian ships only a find module
find_package(glm CONFIG REQUIRED)
find_package(glfw3 CONFIG REQUIRED)
find_package(OpenGL REQUIRED COMPONENTS EGL)
find_package(PkgConfig REQUIRED)
pkg_check_modules(epoxy REQUIRED IMPORTED_TARGET epoxy)
pkg_check_modules(zstd REQUIRED IMPORTED_TARGET libzstd)  # the shards' patch payloads
pkg_check_modules(webp REQUIRED IMPORTED_TARGET libwebp)  # imagery tiles' payloads
pkg_check_modules(curl REQUIRED IMPORTED_TARGET libcurl)  # pyramids at an http(s):// URL
find_package(nlohmann_json CONFIG REQUIRED)
find_package(fmt CONFIG REQUIRED)
if(TERRAIN_BUILD_TOOLS OR TERRAIN_BUILD_TESTS)
  find_package(CLI11 CONFIG REQUIRED)
endif()
if(TERRAIN_BUILD_TESTS)
  find_package(GTest CONFIG REQUIRED)
endif()

# GeographicLib's Debian find module sets variables only; wrap them in a target.
if(NOT TARGET GeographicLib::GeographicLib)
  add_library(GeographicLib::GeographicLib UNKNOWN IMPORTED)
  set_target_properties(GeographicLib::GeographicLib PROPERTIES
    IMPORTED_LOCATION "${GeographicLib_LIBRARIES}"
    INTERFACE_INCLUDE_DIRECTORIES "${GeographicLib_INCLUDE_DIRS}")
endif()

# Debian 12's OpenImageIO package lists /usr/include/opencv4 among its include folders,
# which exists only with libopencv-dev installed, and CMake refuses to generate with a
# missing folder there. Keep only the folders that exist.
get_target_property(_oiio_includes OpenImageIO::OpenImageIO INTERFACE_INCLUDE_DIRECTORIES)
if(_oiio_includes)
  set(_oiio_existing "")
  foreach(_dir IN LISTS _oiio_includes)
    if(EXISTS "${_dir}" OR _dir MATCHES "^\\$<")
      list(APPEND _oiio_existing "${_dir}")
    endif()
  endforeach()
  set_target_properties(OpenImageIO::OpenImageIO PROPERTIES
    INTERFACE_INCLUDE_DIRECTORIES "${_oiio_existing}")
endif()

# Dear ImGui for terrain-view's overlay. Debian 12's libimgui-dev ships a static libimgui.a
# that already holds the GLFW and OpenGL 3 backends (headers under backends/), and an
# imgui.pc that pulls in stb (its font rasteriser); the imported target carries both.
if(TERRAIN_BUILD_TOOLS)
  pkg_check_modules(imgui REQUIRED IMPORTED_TARGET imgui)
endif()
