// TerrainRenderer: camera-relative instance records (double → float after subtracting the
// camera's anchor sample), then one glDrawArraysInstanced of 4 vertices per block and skirt
// primitive (terrain_patches.glsl lists them).
#include "terrain/runtime/TerrainRenderer.h"

#include "InstancedPatchDraw.h"
#include "terrain/base/Assert.h"
#include "terrain/pyramid/PatchErrors.h"
#include "terrain/runtime/CoarseCells.h"
#include "terrain/runtime/ProgramBuilder.h"
#include "terrain/runtime/TerrainFrameUniforms.h"

#include <epoxy/gl.h>
#include <glm/gtc/type_ptr.hpp>

#include <algorithm>
#include <bit>
#include <cmath>

namespace terrain::runtime {

Result<TerrainRenderer> TerrainRenderer::create(const io::PyramidLayout& layout, int maxInstances,
                                                const TerrainRendererOptions& options) {
    TERRAIN_ASSERT(maxInstances >= 1);
    ProgramBuilder builder("terrain");
    builder.stage("terrain.vert").stage("terrain.tesc").stage("terrain.tese").stage("terrain.frag");
    if (options.fragmentNormals) builder.define("TERRAIN_FRAGMENT_NORMALS");
    if (options.recordTessFactors) builder.define("TERRAIN_DEBUG_TESS_FACTORS");
    auto program = builder.build();
    if (!program) return program.error();
    auto primitives = gl::Query::create(gl::QueryKind::PrimitivesGenerated, "terrain triangles");
    if (!primitives) return primitives.error();
    auto time = gl::Query::create(gl::QueryKind::TimeElapsed, "terrain GPU time");
    if (!time) return time.error();

    TerrainRenderer r;
    r.m_program = std::move(program).value();
    r.m_primitivesQuery = std::move(primitives).value();
    r.m_timeQuery = std::move(time).value();
    r.m_vertexArray = gl::VertexArray::create("terrain patches (attribute-less)");
    r.m_maxInstances = maxInstances;
    r.m_blocksPerSide = layout.blocksPerSide();
    r.m_blockQuads = layout.blockQuads();
    r.m_instances =
        gl::Buffer::create(sizeof(PatchInstanceRecord) * static_cast<std::size_t>(maxInstances),
                           GL_DYNAMIC_STORAGE_BIT, "terrain patch instances");
    if (options.recordTessFactors) {
        r.m_tessFactors = gl::Buffer::create(
            sizeof(RecordedTessFactors) * static_cast<std::size_t>(maxInstances) *
                static_cast<std::size_t>(r.primitivesPerInstance(true)),
            0, "terrain tessellation factors (debug)");
    }
    r.m_staging.reserve(static_cast<std::size_t>(maxInstances));
    return r;
}

int TerrainRenderer::primitivesPerInstance(bool skirts) const {
    return m_blocksPerSide * m_blocksPerSide + (skirts ? 4 * m_blocksPerSide : 0);
}

TerrainDrawStats TerrainRenderer::draw(const Camera& camera, const TerrainGeometry& geometry,
                                       const cache::GpuTilePool& pool,
                                       std::span<const PatchDraw> patches,
                                       const TerrainStyle& style, double errorPx) {
    prepare(camera, geometry, pool, patches, style, errorPx);
    return submit(pool);
}

void TerrainRenderer::prepare(const Camera& camera, const TerrainGeometry& geometry,
                              const cache::GpuTilePool& pool, std::span<const PatchDraw> patches,
                              const TerrainStyle& style, double errorPx) {
    TERRAIN_ASSERT(patches.size() <= static_cast<std::size_t>(m_maxInstances),
                   "TerrainRenderer: more patches than instances");
    m_preparedInstances = static_cast<int>(patches.size());
    m_skirts = style.skirts;
    m_wireframe = style.wireframe;
    m_measure = style.measure;
    if (patches.empty()) return;

    // Patch origins reach the GPU relative to the anchor, as every position does
    // (terrainPositionM).
    const io::PyramidLayout& layout = geometry.layout();
    const glm::dvec2 anchor = setCameraFrameUniforms(m_program, camera, geometry);
    writePatchInstanceRecords(layout, pool, patches, anchor, m_staging);
    const Camera& lodCamera = style.lodCamera ? *style.lodCamera : camera;
    if (style.coarseCells && style.fixedTessFactor == 0) {
        // A patch drawn as cells has the cells' Λ: the skirts of every patch must reach it
        // too (SkirtDepth.h: a skirt drops its own edge error plus any neighbour's Λ).
        float coarseDepthM = 0.0f;
        for (std::size_t i = 0; i < patches.size(); ++i) {
            const CoarseCellChoice choice =
                coarseCellChoice(lodCamera, geometry, patches[i].id, *pool.info(patches[i].id),
                                 pool.coarseCellErrorsM(patches[i].id), errorPx);
            if (!choice.coarse()) continue;
            const float errorM = io::roundUpToFloat(choice.errorM);  // a bound: rounded up
            m_staging[i].coarseCells = {static_cast<float>(choice.cellQuads), errorM, 0.0f, 0.0f};
            coarseDepthM = std::max(coarseDepthM, errorM);
        }
        for (PatchInstanceRecord& record : m_staging) {
            record.errors[1] = std::max(record.errors[1], coarseDepthM);
        }
    }
    m_instances.upload(0, std::as_bytes(std::span(m_staging)));

    m_program.setUniform("u_blocksPerSide", m_blocksPerSide);
    m_program.setUniform("u_blockQuads", m_blockQuads);
    m_program.setUniform("u_viewportPx",
                         std::array<float, 2>{static_cast<float>(camera.viewportWidth),
                                              static_cast<float>(camera.viewportHeight)});
    m_program.setUniform("u_errorPx", static_cast<float>(errorPx));
    m_program.setUniform("u_fixedSimplification",
                         fixedSimplification(style.fixedTessFactor, m_blockQuads));
    m_program.setUniform("u_cullBlocks", style.cullBlocks ? 1 : 0);
    const glm::mat4 lodViewProjection(lodCamera.relativeViewProjection());
    m_program.setUniformMat4("u_lodViewProjection",
                             std::span<const float, 16>(glm::value_ptr(lodViewProjection), 16));
    const glm::vec3 lodOffsetM(camera.position - lodCamera.position);
    m_program.setUniform("u_lodOffsetM",
                         std::array<float, 3>{lodOffsetM.x, lodOffsetM.y, lodOffsetM.z});
    setRelativeFrustumUniform(m_program, camera);
    setShadingUniforms(m_program, geometry, style.skyColor, style.fogDensityPerM);
    m_program.setUniform("u_debugView", static_cast<int>(style.debugView));
}

TerrainDrawStats TerrainRenderer::submit(const cache::GpuTilePool& pool) {
    const TerrainDrawStats stats = issueInstancedPatchDraw(
        pool, {.program = m_program,
               .vertexArray = m_vertexArray,
               .instances = m_instances,
               .tessFactors = m_tessFactors.valid() ? &m_tessFactors : nullptr,
               .verticesPerInstance = 4 * primitivesPerInstance(m_skirts),
               .instanceCount = m_preparedInstances,
               .wireframe = m_wireframe,
               .primitivesQuery = m_measure ? &m_primitivesQuery : nullptr,
               .timeQuery = m_measure ? &m_timeQuery : nullptr});
    m_preparedInstances = 0;
    return stats;
}

std::vector<RecordedTessFactors> TerrainRenderer::readTessFactors(int instances) const {
    TERRAIN_ASSERT(m_tessFactors.valid(), "TerrainRenderer: created without recordTessFactors");
    TERRAIN_ASSERT(instances >= 0 && instances <= m_maxInstances);
    std::vector<RecordedTessFactors> records(static_cast<std::size_t>(instances) *
                                             static_cast<std::size_t>(primitivesPerInstance(true)));
    glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);  // the control stage's writes, then a read
    m_tessFactors.readBack(0, std::as_writable_bytes(std::span(records)));
    return records;
}

}  // namespace terrain::runtime
