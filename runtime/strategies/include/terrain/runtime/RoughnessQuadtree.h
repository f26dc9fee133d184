// RoughnessQuadtree: the preprocessing of Lee & Shin 2011, "Geometry splitting" (§2.1–2.2):
// the quadtree texture of surface roughness values σ, one per block, stored at the block's
// centre sample in a texture as large as the height field (Fig. 5), and the height range of
// every block for the bounding spheres of its LOD test (Eq. 2) and its view-frustum culling
// (§3, Fig. 10).
//
// The raster (width × height) is padded to the paper's n × n grid, n = 2^d + 1 (§1). A block
// is a square of 2h × 2h quads around its centre (cx, cy); the root has h = 2^(d−1), and the
// finest blocks, h = 1, are 2 × 2 quads, the smallest with the five midpoints of Fig. 2. A
// finest block that splits is drawn at full resolution (its four quads).
//
// σ (Eq. 3, with the doubling of Fig. 4): σ = max_k δ_k for a finest block, and
// max(max_k δ_k, 2 · σ_child) above, where δ_k is the vertical distance between the sample
// at the block's centre or an edge's midpoint and the block's own surface there (the mean of
// the diagonal's or the edge's two corners). A block that overhangs the raster gets
// kForceSplit, so only blocks inside it are ever drawn whole.
#pragma once

#include "terrain/base/Result.h"

#include <glm/vec2.hpp>

#include <cstddef>
#include <span>
#include <vector>

namespace terrain::runtime {

class RoughnessQuadtree {
public:
    /// σ of a block that overhangs the raster: larger than any projection can shrink below
    /// a pixel, finite so that doubling it stays finite.
    static constexpr float kForceSplit = 1.0e30f;

    /// Bytes build() holds for a width × height raster (σ and the height ranges), before
    /// anything is computed.
    static std::size_t bytesFor(int width, int height);
    /// d: the smallest with 2^d + 1 ≥ max(width, height), at least 1.
    static int depthFor(int width, int height);

    /// `heights`: width × height samples, row-major, rows running south (≥ 2 a side).
    static Result<RoughnessQuadtree> build(int width, int height, std::span<const float> heights);

    int depth() const { return m_depth; }
    int side() const { return m_side; }  ///< n = 2^d + 1
    int width() const { return m_width; }
    int height() const { return m_height; }

    /// σ at every sample of the n × n grid (row-major): a block's at its centre, 0 where no
    /// block is centred.
    const std::vector<float>& roughness() const { return m_roughness; }
    float roughnessAt(int cx, int cy) const {
        return m_roughness[static_cast<std::size_t>(cy) * m_side + cx];
    }

    /// Min and max height of the blocks with half size h = 2^level over their samples
    /// (clamped to the raster), indexed by ((cy − h) / 2h) · blocksPerSide(level) +
    /// (cx − h) / 2h: the mip chain of the range texture, level 0 the finest blocks.
    const std::vector<glm::vec2>& heightRange(int level) const { return m_heightRange[level]; }
    int blocksPerSide(int level) const { return (m_side - 1) >> (level + 1); }

private:
    int m_width = 0, m_height = 0, m_depth = 0, m_side = 0;
    std::vector<float> m_roughness;
    std::vector<std::vector<glm::vec2>> m_heightRange;
};

}  // namespace terrain::runtime
