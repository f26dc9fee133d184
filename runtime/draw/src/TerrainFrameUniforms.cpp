// TerrainFrameUniforms: the uniforms shared by the LOD draw and the reference draw.
#include "terrain/runtime/TerrainFrameUniforms.h"

#include <glm/gtc/type_ptr.hpp>

#include <span>

namespace terrain::runtime {
namespace {

/// Towards the sun, unit length, world frame (x east, y north, z up): from the north-west,
/// 33° above the horizon, the classic hillshade light.
constexpr std::array<float, 3> kSunDirection{-0.5345f, 0.6414f, 0.5505f};

std::array<float, 2> floats(const glm::dvec2& v) {
    return {static_cast<float>(v.x), static_cast<float>(v.y)};
}

}  // namespace

glm::dvec2 setCameraFrameUniforms(gl::Program& program, const Camera& camera,
                                  const TerrainGeometry& geometry) {
    const io::PyramidLayout& layout = geometry.layout();
    const glm::dvec2 cameraSample = geometry.sampleOfWorld(camera.position.x, camera.position.y);
    const glm::dvec2 anchor = glm::floor(cameraSample);
    const glm::dvec2 lastSample{static_cast<double>(layout.rasterWidth() - 1),
                                static_cast<double>(layout.rasterHeight() - 1)};
    const glm::mat4 viewProjection(camera.relativeViewProjection());
    program.setUniform("u_cameraSampleFraction", floats(cameraSample - anchor));
    program.setUniform("u_sampleSpacingM", floats(geometry.sampleSpacing()));
    program.setUniform("u_cameraHeightM", static_cast<float>(camera.position.z));
    program.setUniformMat4("u_viewProjection",
                           std::span<const float, 16>(glm::value_ptr(viewProjection), 16));
    program.setUniform("u_demFirstSample", floats(-anchor));
    program.setUniform("u_demLastSample", floats(lastSample - anchor));
    return anchor;
}

void setShadingUniforms(gl::Program& program, const TerrainGeometry& geometry,
                        const std::array<float, 3>& skyColor, float fogDensityPerM) {
    program.setUniform("u_sunDirection", kSunDirection);
    program.setUniform("u_heightRangeM",
                       std::array<float, 2>{static_cast<float>(geometry.minHeight()),
                                            static_cast<float>(geometry.maxHeight())});
    program.setUniform("u_skyColor", skyColor);
    program.setUniform("u_fogDensityPerM", fogDensityPerM);
}

}  // namespace terrain::runtime
