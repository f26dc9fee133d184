// CdlodRenderer: the patch's sample grid (SampleGrid), instanced once a patch.
#include "terrain/runtime/CdlodRenderer.h"

#include "InstancedPatchDraw.h"

namespace terrain::runtime {

Result<CdlodRenderer> CdlodRenderer::create(const io::PyramidLayout& layout, int maxInstances) {
    auto draw = MethodPatchDraw::create("cdlod", {"cdlod.vert", "terrain.frag"}, maxInstances);
    if (!draw) return draw.error();
    CdlodRenderer r;
    r.m_draw = std::move(draw).value();
    r.m_grid = SampleGrid::create(layout.patchQuads(), "cdlod grid");
    r.m_gridQuads = layout.patchQuads();
    return r;
}

TerrainDrawStats CdlodRenderer::draw(const Camera& camera, const TerrainGeometry& geometry,
                                     const cache::GpuTilePool& pool,
                                     std::span<const PatchDraw> patches, const TerrainStyle& style,
                                     double errorPx) {
    if (patches.empty()) return {};
    m_draw.prepare(camera, geometry, pool, patches, style, errorPx);
    const io::PyramidLayout& layout = geometry.layout();
    setTessellation(m_draw.frame, layout.blocksPerSide(), layout.blockQuads(), m_gridQuads, -1);
    m_draw.uploadFrame();
    gl::Program& program = m_draw.program;
    program.setUniform("u_gridQuads", m_gridQuads);
    program.setUniform("u_rangePerMetre", static_cast<float>(camera.errorScale() / errorPx));
    program.setUniform("u_morphStartRatio", kMorphStartRatio);
    return issueInstancedPatchDraw(pool, {.program = program,
                                          .vertexArray = m_grid.vertexArray(),
                                          .frame = m_draw.frameBuffer.buffer(),
                                          .instances = m_draw.instances,
                                          .indexCount = m_grid.indexCount(),
                                          .instanceCount = static_cast<int>(patches.size()),
                                          .wireframe = style.wireframe,
                                          .primitivesQuery = m_draw.primitivesIf(style),
                                          .timeQuery = m_draw.timeIf(style)});
}

}  // namespace terrain::runtime
