// TerrainShading: the C++ half of shaders/terrain_shading.glsl, the terrain's look shared
// by the LOD draw and the reference renderer.
#pragma once

#include <array>

namespace terrain::runtime {

/// Towards the sun, unit length, world frame (x east, y north, z up): from the north-west,
/// 33° above the horizon, the classic hillshade light.
inline constexpr std::array<float, 3> kTerrainSunDirection{-0.5345f, 0.6414f, 0.5505f};

}  // namespace terrain::runtime
