// TerrainRenderer: camera-relative instance records from the surface's placement (double →
// float after subtracting what is planet-sized), the frame block, then one
// glDrawArraysInstanced of 4 vertices per block and skirt primitive (terrain_primitives.glsl
// lists them).
#include "terrain/runtime/TerrainRenderer.h"

#include "InstancedPatchDraw.h"
#include "terrain/base/Assert.h"
#include "terrain/pyramid/PatchErrors.h"
#include "terrain/runtime/CoarseCells.h"
#include "terrain/runtime/ProgramBuilder.h"

#include <epoxy/gl.h>

#include <algorithm>

namespace terrain::runtime {

static_assert(kMaxDrawnImageryLayers == TERRAIN_MAX_IMAGERY_LAYERS);

namespace {

/// Uploads `items` into `buffer`, first replacing it with a larger one when they do not fit
/// (twice what they need: a few frames grow it, then it stays).
template <typename T>
void uploadGrowing(gl::Buffer& buffer, std::span<const T> items, const char* label) {
    const std::size_t bytes = std::max<std::size_t>(items.size_bytes(), sizeof(T));
    if (!buffer.valid() || buffer.sizeBytes() < bytes)
        buffer = gl::Buffer::create(2 * bytes, GL_DYNAMIC_STORAGE_BIT, label);
    if (!items.empty()) buffer.upload(0, std::as_bytes(items));
}

}  // namespace

Result<TerrainRenderer> TerrainRenderer::create(const Surface& surface, int maxInstances,
                                                const TerrainRendererOptions& options) {
    TERRAIN_ASSERT(maxInstances >= 1);
    std::unique_ptr<SurfacePlacement> placement = SurfacePlacement::forSurface(surface);
    const std::string name(surfaceName(surface.kind()));
    const auto build = [&](bool texelsPerPixel) {
        ProgramBuilder builder("terrain (" + name + (texelsPerPixel ? ", texels per pixel)" : ")"));
        builder.stage("terrain.vert")
            .stage("terrain.tesc")
            .stage("terrain.tese")
            .stage("terrain.frag");
        placement->defineSurface(builder);
        // Shading from the full-resolution mesh at each fragment (terrain.frag), on either
        // surface.
        if (options.fragmentNormals) builder.define("TERRAIN_FRAGMENT_NORMALS");
        if (options.recordTessFactors) builder.define("TERRAIN_DEBUG_TESS_FACTORS");
        if (texelsPerPixel) builder.define("TERRAIN_IMAGERY_TEXELS_PER_PIXEL");
        return builder.build();
    };
    auto program = build(false);
    if (!program) return program.error();
    gl::Program texelsPerPixelProgram;
    if (options.imageryTexelsPerPixel) {
        auto variant = build(true);
        if (!variant) return variant.error();
        texelsPerPixelProgram = std::move(variant).value();
    }
    auto primitives = gl::Query::create(gl::QueryKind::PrimitivesGenerated, name + " triangles");
    if (!primitives) return primitives.error();
    auto time = gl::Query::create(gl::QueryKind::TimeElapsed, name + " GPU time");
    if (!time) return time.error();

    const io::PyramidLayout& layout = surface.layout();
    TerrainRenderer r;
    r.m_surface = &surface;
    r.m_placement = std::move(placement);
    r.m_program = std::move(program).value();
    r.m_texelsPerPixelProgram = std::move(texelsPerPixelProgram);
    r.m_primitivesQuery = std::move(primitives).value();
    r.m_timeQuery = std::move(time).value();
    r.m_vertexArray = gl::VertexArray::create("terrain patches (attribute-less)");
    r.m_maxInstances = maxInstances;
    r.m_blocksPerSide = layout.blocksPerSide();
    r.m_blockQuads = layout.blockQuads();
    r.m_instances =
        gl::Buffer::create(sizeof(PatchInstance) * static_cast<std::size_t>(maxInstances),
                           GL_DYNAMIC_STORAGE_BIT, "terrain patch instances");
    r.m_shadingTiles = gl::Buffer::create(sizeof(ShadingTile) * kShadingAncestors *
                                              static_cast<std::size_t>(maxInstances),
                                          GL_DYNAMIC_STORAGE_BIT, "terrain shading tiles");
    r.m_frameBuffer = FrameBlockBuffer::create("terrain frame block");
    if (options.recordTessFactors) {
        r.m_tessFactors = gl::Buffer::create(
            sizeof(RecordedTessFactors) * static_cast<std::size_t>(maxInstances) *
                static_cast<std::size_t>(r.primitivesPerInstance(true)),
            0, "terrain tessellation factors (debug)");
    }
    r.m_staging.reserve(static_cast<std::size_t>(maxInstances));
    r.m_shadingStaging.reserve(static_cast<std::size_t>(maxInstances) * kShadingAncestors);
    return r;
}

int TerrainRenderer::primitivesPerInstance(bool skirts) const {
    return m_blocksPerSide * m_blocksPerSide + (skirts ? 4 * m_blocksPerSide : 0);
}

TerrainDrawStats TerrainRenderer::draw(const Camera& camera, const cache::GpuTilePool& pool,
                                       std::span<const PatchDraw> patches,
                                       const TerrainStyle& style, double errorPx,
                                       const DrapedImagery* imagery) {
    prepare(camera, pool, patches, style, errorPx, imagery);
    return submit(pool);
}

void TerrainRenderer::prepare(const Camera& camera, const cache::GpuTilePool& pool,
                              std::span<const PatchDraw> patches, const TerrainStyle& style,
                              double errorPx, const DrapedImagery* imagery) {
    TERRAIN_ASSERT(patches.size() <= static_cast<std::size_t>(m_maxInstances),
                   "TerrainRenderer: more patches than instances");
    m_preparedInstances = static_cast<int>(patches.size());
    m_skirts = style.skirts;
    m_wireframe = style.wireframe;
    m_measure = style.measure;
    TERRAIN_ASSERT(
        !style.imageryTexelsPerPixel || m_texelsPerPixelProgram.valid(),
        "TerrainRenderer: imageryTexelsPerPixel needs the renderer's option of that name");
    m_texelsPerPixel = style.imageryTexelsPerPixel;
    if (patches.empty()) return;

    const Camera& lodCamera = style.lodCamera ? *style.lodCamera : camera;
    m_placement->beginFrame(camera, m_frame);
    m_staging.clear();
    for (const PatchDraw& patch : patches) m_staging.push_back(m_placement->place(patch, pool));
    const TerrainGeometry* plane = m_placement->planeGeometry();
    if (plane != nullptr && style.coarseCells && style.fixedTessFactor == 0) {
        // A patch drawn as cells has the cells' Λ: the skirts of every patch must reach it
        // too (SkirtDepth.h: a skirt drops its own edge error plus any neighbour's Λ).
        float coarseDepthM = 0.0f;
        for (std::size_t i = 0; i < patches.size(); ++i) {
            const CoarseCellChoice choice =
                coarseCellChoice(lodCamera, *plane, patches[i].id, *pool.info(patches[i].id),
                                 pool.coarseCellErrorsM(patches[i].id), errorPx);
            if (!choice.coarse()) continue;
            const float errorM = io::roundUpToFloat(choice.errorM);  // a bound: rounded up
            m_staging[i].coarseCells = {static_cast<float>(choice.cellQuads), errorM, 0.0f, 0.0f};
            coarseDepthM = std::max(coarseDepthM, errorM);
        }
        for (PatchInstance& record : m_staging) {
            record.errors[1] = std::max(record.errors[1], coarseDepthM);
        }
    }
    m_instances.upload(0, std::as_bytes(std::span(m_staging)));
    // The tiles above each patch's own for its footprint-filtered normals: resident, as the
    // LOD pins its patches' ancestors (a tile not resident ends the list).
    const int patchQuads = m_surface->layout().patchQuads();
    m_shadingStaging.resize(patches.size() * kShadingAncestors);
    for (std::size_t i = 0; i < patches.size(); ++i) {
        const PatchDraw& p = patches[i];
        shadingTilesOf({.id = p.tileId,
                        .texelOffset = p.texelOffset,
                        .texelStep = p.texelStep,
                        .layer = p.layer},
                       patchQuads,
                       [&pool](AncestorTile& a) {
                           return pool.isResident(a.id) ? pool.layerOf(a.id) : std::nullopt;
                       },
                       std::span<ShadingTile, kShadingAncestors>(
                           m_shadingStaging.data() + i * kShadingAncestors, kShadingAncestors));
    }
    m_shadingTiles.upload(0, std::as_bytes(std::span(m_shadingStaging)));

    setCameraFrame(m_frame, camera, lodCamera, errorPx);
    setTessellation(m_frame, m_blocksPerSide, m_blockQuads, m_surface->layout().patchQuads(),
                    fixedSimplification(style.fixedTessFactor, m_blockQuads));
    setLook(m_frame, style);
    m_imageryTiles = nullptr;
    if (imagery != nullptr && style.imagery && style.debugView == TerrainDebugView::Shaded)
        m_frame.options[2] = prepareImagery(*imagery, patches.size(), style);
    m_frameBuffer.upload(m_frame);
}

int TerrainRenderer::prepareImagery(const DrapedImagery& imagery, std::size_t patches,
                                    const TerrainStyle& style) {
    const ImagerySelection& selection = imagery.selection;
    const int layers = std::min(selection.layerCount(), kMaxDrawnImageryLayers);
    if (layers == 0) return 0;
    TERRAIN_ASSERT(selection.roots().size() == patches * static_cast<std::size_t>(layers),
                   "TerrainRenderer: the imagery was selected for other patches");
    uploadGrowing(m_imageryRoots, selection.roots(), "terrain imagery roots");
    uploadGrowing(m_imageryNodes, selection.nodes(), "terrain imagery nodes");
    uploadGrowing(m_imageryChildren, selection.children(), "terrain imagery children");
    for (int l = 0; l < kMaxDrawnImageryLayers; ++l) {
        const auto i = static_cast<std::size_t>(l);
        m_frame.imageryOpacity[i] =
            l < layers ? static_cast<float>(selection.layerOpacity(l)) * style.imageryOpacity[i]
                       : 0.0f;
    }
    m_frame.imageryOrder = imageryDrawOrder(style, layers);
    m_frame.imagerySampling = {std::max(1.0f, imagery.maxAnisotropy), 0.0f, 0.0f, 0.0f};
    m_imageryTiles = &imagery.tiles;
    return layers;
}

TerrainDrawStats TerrainRenderer::submit(const cache::GpuTilePool& pool) {
    if (m_imageryTiles != nullptr) {
        glBindTextureUnit(TERRAIN_BINDING_IMAGERY_TILES, m_imageryTiles->id());
        glBindBufferBase(GL_SHADER_STORAGE_BUFFER, TERRAIN_BINDING_IMAGERY_ROOTS,
                         m_imageryRoots.id());
        glBindBufferBase(GL_SHADER_STORAGE_BUFFER, TERRAIN_BINDING_IMAGERY_NODES,
                         m_imageryNodes.id());
        glBindBufferBase(GL_SHADER_STORAGE_BUFFER, TERRAIN_BINDING_IMAGERY_CHILDREN,
                         m_imageryChildren.id());
    }
    TerrainDrawStats stats = issueInstancedPatchDraw(
        pool, {.program = m_texelsPerPixel ? m_texelsPerPixelProgram : m_program,
               .vertexArray = m_vertexArray,
               .frame = m_frameBuffer.buffer(),
               .instances = m_instances,
               .shadingTiles = &m_shadingTiles,
               .tessFactors = m_tessFactors.valid() ? &m_tessFactors : nullptr,
               .verticesPerInstance = 4 * primitivesPerInstance(m_skirts),
               .instanceCount = m_preparedInstances,
               .wireframe = m_wireframe,
               .primitivesQuery = m_measure ? &m_primitivesQuery : nullptr,
               .timeQuery = m_measure ? &m_timeQuery : nullptr});
    if (m_imageryTiles != nullptr) {
        for (const int binding : {TERRAIN_BINDING_IMAGERY_ROOTS, TERRAIN_BINDING_IMAGERY_NODES,
                                  TERRAIN_BINDING_IMAGERY_CHILDREN})
            glBindBufferBase(GL_SHADER_STORAGE_BUFFER, static_cast<GLuint>(binding), 0);
        glBindTextureUnit(TERRAIN_BINDING_IMAGERY_TILES, 0);
    }
    m_preparedInstances = 0;
    stats.imageryLayers = m_frame.options[2];
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
