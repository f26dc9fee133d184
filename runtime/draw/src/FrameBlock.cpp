// FrameBlock: double → float after everything planet-sized is subtracted.
#include "terrain/runtime/FrameBlock.h"

#include "InstancedPatchDraw.h"

#include <epoxy/gl.h>
#include <glm/geometric.hpp>
#include <glm/gtc/type_ptr.hpp>

#include <cmath>
#include <cstring>
#include <span>

namespace terrain::runtime {
namespace {

std::array<float, 16> floats(const glm::dmat4& m) {
    const glm::mat4 single(m);
    std::array<float, 16> out{};
    std::memcpy(out.data(), glm::value_ptr(single), sizeof(out));
    return out;
}

}  // namespace

void setCameraFrame(FrameBlock& block, const Camera& camera, const Camera& lodCamera,
                    double errorPx) {
    block.viewProjection = floats(camera.relativeViewProjection());
    block.lodViewProjection = floats(lodCamera.relativeViewProjection());
    const std::array<float, 20> planes = relativeFrustumPlanes(camera);
    for (std::size_t i = 0; i < block.frustumPlanes.size(); ++i)
        for (std::size_t c = 0; c < 4; ++c) block.frustumPlanes[i][c] = planes[4 * i + c];
    const glm::vec3 lodOffsetM(camera.position - lodCamera.position);
    block.lodOffsetM = {lodOffsetM.x, lodOffsetM.y, lodOffsetM.z, 0.0f};
    block.screen = {static_cast<float>(camera.viewportWidth),
                    static_cast<float>(camera.viewportHeight), static_cast<float>(errorPx),
                    static_cast<float>(camera.nearPlane)};
    // A point in the frustum has |p| ≤ depth · √(1 + tan²x + tan²y); a segment of length e
    // at distance D from the camera then spans at most e · f · (1 + tan²x + tan²y) / D
    // pixels, f the focal length in pixels.
    const double tanY = std::tan(0.5 * camera.fovY);
    const double tanX = std::tan(0.5 * camera.fovX());
    const double focalPx = 0.5 * static_cast<double>(camera.viewportHeight) / tanY;
    block.pixelsPerMetre = {static_cast<float>(focalPx * (1.0 + tanX * tanX + tanY * tanY)),
                            static_cast<float>(camera.errorScale()), 0.0f, 0.0f};
}

void setTessellation(FrameBlock& block, int blocksPerSide, int blockQuads, int patchQuads,
                     int fixedSimplification) {
    block.tessellation = {blocksPerSide, blockQuads, patchQuads, fixedSimplification};
}

void setLook(FrameBlock& block, const TerrainStyle& style) {
    // Imagery layers (options.z) and their opacities are the renderer's: it knows the layers.
    block.options = {style.cullBlocks ? 1 : 0, static_cast<std::int32_t>(style.debugView), 0,
                     style.imageryLighting ? 1 : 0};
    block.sky = {style.skyColor[0], style.skyColor[1], style.skyColor[2], style.fogDensityPerM};
}

FrameBlockBuffer FrameBlockBuffer::create(const std::string& label) {
    FrameBlockBuffer b;
    b.m_buffer = gl::Buffer::create(sizeof(FrameBlock), GL_DYNAMIC_STORAGE_BIT, label);
    return b;
}

void FrameBlockBuffer::upload(const FrameBlock& block) {
    m_buffer.upload(0, std::as_bytes(std::span(&block, 1)));
}

}  // namespace terrain::runtime
