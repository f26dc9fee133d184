// TerrainFrameUniforms: the uniforms the LOD draw (TerrainRenderer) and the reference draw
// (ReferenceRenderer) share, so both place and shade the terrain identically: the
// camera-relative frame of terrain_patches.glsl / reference.vert and the look of
// terrain_shading.glsl.
#pragma once

#include "terrain/gl/Program.h"
#include "terrain/runtime/Camera.h"
#include "terrain/runtime/TerrainGeometry.h"

#include <glm/glm.hpp>

#include <array>

namespace terrain::runtime {

/// Sets u_cameraSampleFraction, u_sampleSpacingM, u_cameraHeightM, u_viewProjection,
/// u_demFirstSample and u_demLastSample. Positions reach the GPU as DEM samples relative to
/// the anchor, the DEM sample at or before the camera: integers, exact in float near the
/// camera. Returns the anchor (DEM samples).
glm::dvec2 setCameraFrameUniforms(gl::Program& program, const Camera& camera,
                                  const TerrainGeometry& geometry);

/// Sets u_sunDirection, u_heightRangeM, u_skyColor and u_fogDensityPerM.
void setShadingUniforms(gl::Program& program, const TerrainGeometry& geometry,
                        const std::array<float, 3>& skyColor, float fogDensityPerM);

}  // namespace terrain::runtime
