// ReferenceRenderer: the frame block for the camera, the scene's instances through the batch.
#include "terrain/runtime/ReferenceRenderer.h"

#include "Bindings.h"
#include "terrain/gl/ReversedZScope.h"

#include <epoxy/gl.h>

namespace terrain::runtime {

Result<ReferenceRenderer> ReferenceRenderer::create(std::unique_ptr<ReferenceScene> scene) {
    auto batch = ReferenceBatch::create(scene->name(), scene->vertexStage(), scene->globe(),
                                        scene->gridQuads(), scene->tileSamples());
    if (!batch) return batch.error();
    ReferenceRenderer r;
    r.m_scene = std::move(scene);
    r.m_batch = std::move(batch).value();
    r.m_frame = FrameBlockBuffer::create(r.m_scene->name() + " frame");
    return r;
}

Result<ReferenceDrawStats> ReferenceRenderer::draw(const Camera& camera,
                                                   const ReferenceStyle& style,
                                                   std::uint64_t maxRegions) {
    // Placed and shaded as the LOD draw, so both draws are equally exact and alike.
    FrameBlock block;
    setCameraFrame(block, camera, camera, 0.0);
    const int quads = m_batch.gridQuads();
    setTessellation(block, 1, quads, quads, -1);  // one grid of quads² cells an instance
    block.sky = {style.skyColor[0], style.skyColor[1], style.skyColor[2], style.fogDensityPerM};
    m_scene->beginFrame(camera, block);
    m_frame.upload(block);

    const gl::ReversedZScope reversedZ;
    glBindBufferBase(GL_UNIFORM_BUFFER, TERRAIN_BINDING_FRAME_BLOCK, m_frame.buffer().id());
    m_batch.reset();
    auto added = m_scene->addInstances(camera, m_batch, maxRegions);
    if (added) m_batch.flush();
    glBindBufferBase(GL_UNIFORM_BUFFER, TERRAIN_BINDING_FRAME_BLOCK, 0);
    if (!added) {
        m_batch.reset();
        return added.error();
    }
    ReferenceDrawStats stats;
    stats.tiles = m_batch.instancesDrawn();
    stats.batches = m_batch.batchesDrawn();
    stats.complete = added.value();
    stats.triangles =
        stats.tiles * 2 * static_cast<std::uint64_t>(quads) * static_cast<std::uint64_t>(quads);
    return stats;
}

}  // namespace terrain::runtime
