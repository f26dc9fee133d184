// ReferenceBatch: how the reference renderer (ReferenceRenderer.h) draws whatever a scene
// holds: one program (a scene's vertex stage and reference.frag), one grid of samples drawn
// as instances (SampleGrid), their records (PatchInstance) and the tiles they read their
// heights from, uploaded into the layers of a texture array as the instances are added and
// drawn kInstances at a time. A tile that several instances of one batch read (a patch's
// quadrants, the parts of a region) is uploaded once.
#pragma once

#include "terrain/base/Result.h"
#include "terrain/gl/Buffer.h"
#include "terrain/gl/Program.h"
#include "terrain/gl/Texture.h"
#include "terrain/runtime/PatchInstance.h"
#include "terrain/runtime/SampleGrid.h"
#include "terrain/runtime/ShadingTiles.h"

#include <cstdint>
#include <functional>
#include <span>
#include <string>
#include <vector>

namespace terrain::runtime {

/// Render thread only; the frame block must be bound (ReferenceRenderer::draw) while
/// instances are added.
class ReferenceBatch {
public:
    /// Instances a draw call takes.
    static constexpr int kInstances = 32;
    /// Layers its texture array holds: each instance reads at most one tile of its own and
    /// kShadingAncestors above it, so a full batch never runs out of layers.
    static constexpr int kLayers = kInstances * (1 + kShadingAncestors);

    /// A batch drawn with `vertexStage` and reference.frag (its normals filtered to the
    /// pixel's footprint, on the globe's surface when `globe`), instances of a grid of
    /// `gridQuads`² cells reading tiles of `tileSamples`² heights. Errors: the program does not
    /// build.
    static Result<ReferenceBatch> create(const std::string& label, const std::string& vertexStage,
                                         bool globe, int gridQuads, int tileSamples);

    /// The layer of the tile `key` (unique within a draw) in this batch: uploaded from
    /// `heights` (tileSamples² floats, rows first) into the next free layer unless the batch
    /// holds it already. Errors: `heights`'.
    Result<int> layerOf(std::uint64_t key,
                        const std::function<Result<std::span<const float>>()>& heights);

    /// Adds an instance (its layer from layerOf, or −1 for none) and the tiles above its own
    /// that its footprint-filtered normals read (ShadingTiles.h, their layers from layerOf);
    /// draws the batch once it holds kInstances.
    void add(const PatchInstance& instance,
             std::span<const ShadingTile, kShadingAncestors> shadingTiles);

    /// Draws what the batch holds, if anything; forgets its tiles.
    void flush();

    /// Forgets what the batch holds without drawing it (a draw that failed), and the counts.
    void reset();

    int gridQuads() const { return m_gridQuads; }
    int tileSamples() const { return m_tileSamples; }
    std::uint64_t instancesDrawn() const { return m_instancesDrawn; }
    int batchesDrawn() const { return m_batchesDrawn; }

private:
    gl::Program m_program;
    SampleGrid m_grid;
    gl::Buffer m_instances;
    gl::Buffer m_shadingTiles;  // kShadingAncestors per instance
    gl::Texture m_heights;      // kLayers layers of tileSamples²
    int m_gridQuads = 0;
    int m_tileSamples = 0;
    std::vector<PatchInstance> m_staging;
    std::vector<ShadingTile> m_shadingStaging;
    std::vector<std::uint64_t> m_layerTiles;  // the tile in each layer of this batch
    std::uint64_t m_instancesDrawn = 0;
    int m_batchesDrawn = 0;
};

}  // namespace terrain::runtime
