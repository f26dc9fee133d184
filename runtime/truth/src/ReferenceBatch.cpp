// ReferenceBatch: instances staged on the CPU, their tiles uploaded as they come, one
// instanced draw of the grid per full batch.
#include "terrain/runtime/ReferenceBatch.h"

#include "Bindings.h"
#include "terrain/base/Assert.h"
#include "terrain/runtime/ProgramBuilder.h"

#include <epoxy/gl.h>

#include <algorithm>

namespace terrain::runtime {

Result<ReferenceBatch> ReferenceBatch::create(const std::string& label,
                                              const std::string& vertexStage, bool globe,
                                              int gridQuads, int tileSamples) {
    ProgramBuilder builder(label);
    builder.define("TERRAIN_REFERENCE_FOOTPRINT");
    if (globe) builder.define("TERRAIN_SURFACE_GLOBE");
    builder.stage(vertexStage).stage("reference.frag");
    auto program = builder.build();
    if (!program) return program.error();
    ReferenceBatch b;
    b.m_program = std::move(program).value();
    b.m_gridQuads = gridQuads;
    b.m_tileSamples = tileSamples;
    b.m_grid = SampleGrid::create(gridQuads, label + " grid");
    b.m_instances = gl::Buffer::create(sizeof(PatchInstance) * kInstances, GL_DYNAMIC_STORAGE_BIT,
                                       label + " instances");
    b.m_shadingTiles = gl::Buffer::create(sizeof(ShadingTile) * kShadingAncestors * kInstances,
                                          GL_DYNAMIC_STORAGE_BIT, label + " shading tiles");
    auto heights = gl::Texture::create2DArray({.internalFormat = GL_R32F,
                                               .width = tileSamples,
                                               .height = tileSamples,
                                               .layers = kLayers},
                                              label + " tiles");
    if (!heights) return heights.error();
    b.m_heights = std::move(heights).value();
    b.m_heights.setSampling(GL_NEAREST, GL_NEAREST, GL_CLAMP_TO_EDGE);
    b.m_staging.reserve(kInstances);
    b.m_shadingStaging.reserve(kInstances * kShadingAncestors);
    b.m_layerTiles.reserve(kLayers);
    return b;
}

Result<int> ReferenceBatch::layerOf(
    std::uint64_t key, const std::function<Result<std::span<const float>>()>& heights) {
    const auto uploaded = std::find(m_layerTiles.begin(), m_layerTiles.end(), key);
    const int layer = static_cast<int>(uploaded - m_layerTiles.begin());
    if (uploaded != m_layerTiles.end()) return layer;
    TERRAIN_ASSERT(layer < kLayers, "ReferenceBatch: more tiles than its instances read");
    auto read = heights();
    if (!read) return read.error();
    TERRAIN_ASSERT(read.value().size() == static_cast<std::size_t>(m_tileSamples) *
                                              static_cast<std::size_t>(m_tileSamples));
    m_heights.upload(
        {.x = 0, .y = 0, .layer = layer, .width = m_tileSamples, .height = m_tileSamples}, GL_RED,
        GL_FLOAT, std::as_bytes(read.value()));
    m_layerTiles.push_back(key);
    return layer;
}

void ReferenceBatch::add(const PatchInstance& instance,
                         std::span<const ShadingTile, kShadingAncestors> shadingTiles) {
    m_staging.push_back(instance);
    m_shadingStaging.insert(m_shadingStaging.end(), shadingTiles.begin(), shadingTiles.end());
    if (static_cast<int>(m_staging.size()) == kInstances) flush();
}

void ReferenceBatch::flush() {
    if (!m_staging.empty()) {
        m_instances.upload(0, std::as_bytes(std::span(m_staging)));
        m_shadingTiles.upload(0, std::as_bytes(std::span(m_shadingStaging)));
        glBindBufferBase(GL_SHADER_STORAGE_BUFFER, TERRAIN_BINDING_SHADING_TILES,
                         m_shadingTiles.id());
        m_grid.draw(m_program, m_heights, m_instances, static_cast<int>(m_staging.size()));
        m_instancesDrawn += m_staging.size();
        ++m_batchesDrawn;
    }
    m_staging.clear();
    m_shadingStaging.clear();
    m_layerTiles.clear();
}

void ReferenceBatch::reset() {
    m_staging.clear();
    m_shadingStaging.clear();
    m_layerTiles.clear();
    m_instancesDrawn = 0;
    m_batchesDrawn = 0;
}

}  // namespace terrain::runtime
