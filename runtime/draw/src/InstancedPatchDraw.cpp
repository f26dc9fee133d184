#include "InstancedPatchDraw.h"

#include "Bindings.h"
#include "terrain/gl/PolygonModeScope.h"
#include "terrain/gl/ReversedZScope.h"

#include "terrain/pyramid/PatchErrors.h"

#include <epoxy/gl.h>
#include <glm/geometric.hpp>

#include <algorithm>
#include <array>
#include <bit>

namespace terrain::runtime {

int fixedSimplification(int factor, int blockQuads) {
    if (factor <= 0) return -1;
    const auto clamped = static_cast<unsigned>(std::clamp(factor, 1, blockQuads));
    const int d = std::countr_zero(static_cast<unsigned>(blockQuads)) -
                  std::countr_zero(std::bit_floor(clamped));
    return std::min(d, io::kMaxSimplification);
}

std::array<float, 20> relativeFrustumPlanes(const Camera& camera) {
    const Frustum frustum = camera.frustum();
    std::array<float, 4 * 5> planes{};
    for (std::size_t i = 0; i < frustum.planes.size(); ++i) {
        const glm::dvec4& p = frustum.planes[i];
        const double w = p.w + glm::dot(glm::dvec3(p), camera.position);
        planes[4 * i + 0] = static_cast<float>(p.x);
        planes[4 * i + 1] = static_cast<float>(p.y);
        planes[4 * i + 2] = static_cast<float>(p.z);
        planes[4 * i + 3] = static_cast<float>(w);
    }
    return planes;
}

TerrainDrawStats issueInstancedPatchDraw(const cache::GpuTilePool& pool,
                                         const InstancedPatchDraw& draw) {
    if (draw.instanceCount == 0) return {};
    const gl::ReversedZScope reversedZ;
    glUseProgram(draw.program.id());
    glBindVertexArray(draw.vertexArray.id());
    glBindTextureUnit(TERRAIN_BINDING_HEIGHTS, pool.heights().id());
    glBindTextureUnit(TERRAIN_BINDING_BLOCK_ERRORS, pool.blockErrors().id());
    glBindTextureUnit(TERRAIN_BINDING_BLOCK_RANGES, pool.blockRanges().id());
    glBindBufferBase(GL_UNIFORM_BUFFER, TERRAIN_BINDING_FRAME_BLOCK, draw.frame.id());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, TERRAIN_BINDING_PATCH_INSTANCES,
                     draw.instances.id());
    if (draw.shadingTiles != nullptr) {
        glBindBufferBase(GL_SHADER_STORAGE_BUFFER, TERRAIN_BINDING_SHADING_TILES,
                         draw.shadingTiles->id());
    }
    if (draw.tessFactors != nullptr) {
        glBindBufferBase(GL_SHADER_STORAGE_BUFFER, TERRAIN_BINDING_DEBUG_TESS_FACTORS,
                         draw.tessFactors->id());
    }
    glPatchParameteri(GL_PATCH_VERTICES, 4);
    const bool measure = draw.primitivesQuery != nullptr && draw.timeQuery != nullptr;
    {
        const gl::PolygonModeScope polygonMode(draw.wireframe);
        if (measure) {
            draw.primitivesQuery->begin();
            draw.timeQuery->begin();
        }
        if (draw.indexCount > 0) {
            glDrawElementsInstanced(GL_TRIANGLES, draw.indexCount, GL_UNSIGNED_INT, nullptr,
                                    static_cast<GLsizei>(draw.instanceCount));
        } else {
            glDrawArraysInstanced(GL_PATCHES, 0, draw.verticesPerInstance,
                                  static_cast<GLsizei>(draw.instanceCount));
        }
        if (measure) {
            draw.timeQuery->end();
            draw.primitivesQuery->end();
        }
    }
    if (draw.tessFactors != nullptr)
        glBindBufferBase(GL_SHADER_STORAGE_BUFFER, TERRAIN_BINDING_DEBUG_TESS_FACTORS, 0);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, TERRAIN_BINDING_PATCH_INSTANCES, 0);
    glBindBufferBase(GL_UNIFORM_BUFFER, TERRAIN_BINDING_FRAME_BLOCK, 0);
    glBindTextureUnit(TERRAIN_BINDING_BLOCK_RANGES, 0);
    glBindTextureUnit(TERRAIN_BINDING_BLOCK_ERRORS, 0);
    glBindTextureUnit(TERRAIN_BINDING_HEIGHTS, 0);
    glBindVertexArray(0);
    glUseProgram(0);

    TerrainDrawStats stats{.drawCalls = 1, .instances = draw.instanceCount};
    if (measure) {
        stats.triangles = draw.primitivesQuery->waitResult();
        stats.gpuMs = static_cast<double>(draw.timeQuery->waitResult()) * 1e-6;
    }
    return stats;
}

}  // namespace terrain::runtime
