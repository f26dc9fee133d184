#include "terrain/runtime/GlobeRenderer.h"

#include "InstancedPatchDraw.h"
#include "terrain/base/Assert.h"
#include "terrain/globe/Wgs84.h"
#include "terrain/pyramid/GlobeLayout.h"
#include "terrain/runtime/ProgramBuilder.h"

#include <epoxy/gl.h>
#include <glm/geometric.hpp>
#include <glm/gtc/type_ptr.hpp>

#include <algorithm>
#include <bit>
#include <cmath>

namespace terrain::runtime {

glm::dvec3 globeSunDirection(const Camera& camera) {
    const glm::dvec3 up = globe::Wgs84::upAt(camera.position);
    return glm::normalize(2.0 * up + camera.right() - 0.5 * camera.forward());
}

std::array<float, 2> globeHeightRange(const io::PyramidManifest& manifest) {
    return {static_cast<float>(std::min(manifest.statistics.minHeight, 0.0)),
            static_cast<float>(std::max(manifest.statistics.maxHeight, 1.0))};
}

Result<GlobeRenderer> GlobeRenderer::create(const io::PyramidManifest& manifest, int maxInstances) {
    TERRAIN_ASSERT(maxInstances >= 1);
    TERRAIN_ASSERT(manifest.globe.has_value(), "GlobeRenderer draws globe pyramids");
    ProgramBuilder builder("globe");
    builder.stage("terrain.vert").stage("globe.tesc").stage("globe.tese").stage("terrain.frag");
    auto program = builder.build();
    if (!program) return program.error();
    auto primitives = gl::Query::create(gl::QueryKind::PrimitivesGenerated, "globe triangles");
    if (!primitives) return primitives.error();
    auto time = gl::Query::create(gl::QueryKind::TimeElapsed, "globe GPU time");
    if (!time) return time.error();
    GlobeRenderer r;
    r.m_program = std::move(program).value();
    r.m_primitivesQuery = std::move(primitives).value();
    r.m_timeQuery = std::move(time).value();
    r.m_vertexArray = gl::VertexArray::create("globe patches (attribute-less)");
    r.m_maxInstances = maxInstances;
    r.m_blocksPerSide = manifest.layout.blocksPerSide();
    r.m_blockQuads = manifest.layout.blockQuads();
    r.m_patchQuads = manifest.layout.patchQuads();
    r.m_heightRange = globeHeightRange(manifest);
    r.m_instances =
        gl::Buffer::create(sizeof(GlobeInstance) * static_cast<std::size_t>(maxInstances),
                           GL_DYNAMIC_STORAGE_BIT, "globe patch instances");
    r.m_staging.reserve(static_cast<std::size_t>(maxInstances));
    return r;
}

void GlobeRenderer::setUniforms(const Camera& camera, const TerrainStyle& style, double errorPx) {
    const glm::mat4 viewProjection(camera.relativeViewProjection());
    m_program.setUniformMat4("u_viewProjection",
                             std::span<const float, 16>(glm::value_ptr(viewProjection), 16));
    m_program.setUniform("u_blocksPerSide", m_blocksPerSide);
    m_program.setUniform("u_blockQuads", m_blockQuads);
    m_program.setUniform("u_patchQuads", m_patchQuads);
    const double tanY = std::tan(0.5 * camera.fovY);
    const double tanX = std::tan(0.5 * camera.fovX());
    const double focalPx = 0.5 * static_cast<double>(camera.viewportHeight) / tanY;
    m_program.setUniform("u_pxPerMAtUnitDistance",
                         static_cast<float>(focalPx * (1.0 + tanX * tanX + tanY * tanY)));
    m_program.setUniform("u_nearM", static_cast<float>(camera.nearPlane));
    m_program.setUniform("u_errorPx", static_cast<float>(errorPx));
    m_program.setUniform("u_fixedSimplification",
                         fixedSimplification(style.fixedTessFactor, m_blockQuads));
    m_program.setUniform("u_cullBlocks", style.cullBlocks ? 1 : 0);
    setRelativeFrustumUniform(m_program, camera);
    const glm::dvec3 sun = globeSunDirection(camera);
    m_program.setUniform("u_sunDirection",
                         std::array<float, 3>{static_cast<float>(sun.x), static_cast<float>(sun.y),
                                              static_cast<float>(sun.z)});
    m_program.setUniform("u_heightRangeM", m_heightRange);
    m_program.setUniform("u_skyColor", style.skyColor);
    m_program.setUniform("u_fogDensityPerM", style.fogDensityPerM);
    m_program.setUniform("u_debugView", static_cast<int>(style.debugView));
    // terrain.frag clips the planar DEM's overhang; a globe has none.
    m_program.setUniform("u_demFirstSample", std::array<float, 2>{-1e30f, -1e30f});
    m_program.setUniform("u_demLastSample", std::array<float, 2>{1e30f, 1e30f});
}

TerrainDrawStats GlobeRenderer::draw(const Camera& camera, const cache::GpuTilePool& pool,
                                     std::span<const PatchDraw> patches, const TerrainStyle& style,
                                     double errorPx) {
    TERRAIN_ASSERT(patches.size() <= static_cast<std::size_t>(m_maxInstances),
                   "GlobeRenderer: more patches than instances");
    if (patches.empty()) return {};
    const glm::dvec3 cameraUp = globe::Wgs84::upAt(camera.position);
    m_staging.clear();
    for (const PatchDraw& p : patches) {
        TERRAIN_ASSERT(p.layer < 0 || pool.layerOf(p.tileId) == p.layer,
                       "GlobeRenderer: drawing a data patch that is not resident on its layer");
        m_staging.push_back(makeGlobeInstance(p, camera.position, cameraUp, m_patchQuads));
    }
    m_instances.upload(0, std::as_bytes(std::span(m_staging)));
    setUniforms(camera, style, errorPx);
    return issueInstancedPatchDraw(
        pool, {.program = m_program,
               .vertexArray = m_vertexArray,
               .instances = m_instances,
               .verticesPerInstance = 4 * (m_blocksPerSide * m_blocksPerSide +
                                           (style.skirts ? 4 * m_blocksPerSide : 0)),
               .instanceCount = static_cast<int>(patches.size()),
               .wireframe = style.wireframe,
               .primitivesQuery = style.measure ? &m_primitivesQuery : nullptr,
               .timeQuery = style.measure ? &m_timeQuery : nullptr});
}

}  // namespace terrain::runtime
